// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/asset/asset_validate.h"

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace dermis {
namespace {

/// Builds JSON pointers piece by piece, only when a fault is reported.
std::string Ptr(const std::string& base, std::size_t index) {
  return base + "/" + std::to_string(index);
}
std::string Ptr(const std::string& base, const char* field) { return base + "/" + field; }

class Checker {
 public:
  explicit Checker(const Asset& asset) : asset_(asset) {}

  Status Fail(const std::string& pointer, const std::string& what) const {
    return Status::InvalidInput(asset_.source + ": " + pointer + ": " + what);
  }

  /// `index` must be in [0, count) or, when `optional`, kInvalidIndex.
  Status CheckIndex(Index index, std::size_t count, bool optional, const std::string& pointer,
                    const char* what) const {
    if (optional && index == kInvalidIndex) return Status::Ok();
    if (index < 0 || static_cast<std::size_t>(index) >= count) {
      return Fail(pointer, std::string(what) + " index " + std::to_string(index) +
                               " out of range (count " + std::to_string(count) + ")");
    }
    return Status::Ok();
  }

  Status Run();

 private:
  Status CheckMesh(std::size_t m);
  Status CheckPrimitive(std::size_t m, std::size_t p);
  Status CheckNodes();
  Status CheckSkin(std::size_t s);
  Status CheckAnimation(std::size_t a);

  const Asset& asset_;
};

bool Finite(float x) { return std::isfinite(x); }
bool Finite(double x) { return std::isfinite(x); }
template <int N, typename T, glm::qualifier Q>
bool Finite(const glm::vec<N, T, Q>& v) {
  for (int i = 0; i < N; ++i) {
    if (!std::isfinite(v[i])) return false;
  }
  return true;
}
template <typename T, glm::qualifier Q>
bool Finite(const glm::qua<T, Q>& q) {
  return std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) && std::isfinite(q.w);
}
template <typename T, glm::qualifier Q>
bool Finite(const glm::mat<4, 4, T, Q>& m) {
  for (int c = 0; c < 4; ++c) {
    if (!Finite(m[c])) return false;
  }
  return true;
}

/// Checks that every element of `values` is finite; on failure sets *bad to its index.
template <typename T>
bool AllFinite(const std::vector<T>& values, std::size_t* bad) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!Finite(values[i])) {
      *bad = i;
      return false;
    }
  }
  return true;
}

/// Checks an optional per-vertex attribute: empty or `count` finite entries.
template <typename T>
Status CheckAttribute(const Checker& c, const std::vector<T>& values, std::size_t count,
                      bool optional, const std::string& pointer) {
  if (values.empty() && optional) return Status::Ok();
  if (values.size() != count) {
    return c.Fail(pointer, "has " + std::to_string(values.size()) + " entries, expected " +
                               std::to_string(count) + " (the vertex count)");
  }
  std::size_t bad = 0;
  if (!AllFinite(values, &bad)) return c.Fail(Ptr(pointer, bad), "not finite");
  return Status::Ok();
}

const char* ModeName(PrimitiveMode mode) {
  switch (mode) {
    case PrimitiveMode::kPoints:
      return "points";
    case PrimitiveMode::kLines:
      return "lines";
    case PrimitiveMode::kLineLoop:
      return "line loop";
    case PrimitiveMode::kLineStrip:
      return "line strip";
    case PrimitiveMode::kTriangles:
      return "triangles";
    case PrimitiveMode::kTriangleStrip:
      return "triangle strip";
    case PrimitiveMode::kTriangleFan:
      return "triangle fan";
  }
  return "?";
}

Status Checker::CheckPrimitive(std::size_t m, std::size_t p) {
  const AssetPrimitive& prim = asset_.meshes[m].primitives[p];
  const std::string ptr = Ptr(Ptr(Ptr(Ptr("", "meshes"), m), "primitives"), p);
  if (static_cast<unsigned>(prim.mode) > static_cast<unsigned>(PrimitiveMode::kTriangleFan)) {
    return Fail(Ptr(ptr, "mode"), "unknown mode " + std::to_string(unsigned(prim.mode)));
  }
  const std::size_t n = prim.positions.size();
  Status s;
  if (!(s = CheckAttribute(*this, prim.positions, n, false, Ptr(ptr, "positions"))).ok()) return s;
  if (!(s = CheckAttribute(*this, prim.normals, n, true, Ptr(ptr, "normals"))).ok()) return s;
  if (!(s = CheckAttribute(*this, prim.tangents, n, true, Ptr(ptr, "tangents"))).ok()) return s;
  for (std::size_t k = 0; k < prim.texcoords.size(); ++k) {
    s = CheckAttribute(*this, prim.texcoords[k], n, false, Ptr(Ptr(ptr, "texcoords"), k));
    if (!s.ok()) return s;
  }
  for (std::size_t k = 0; k < prim.colors.size(); ++k) {
    s = CheckAttribute(*this, prim.colors[k], n, false, Ptr(Ptr(ptr, "colors"), k));
    if (!s.ok()) return s;
  }
  if (prim.joints.size() != prim.weights.size()) {
    return Fail(Ptr(ptr, "weights"), std::to_string(prim.joints.size()) + " joint sets but " +
                                         std::to_string(prim.weights.size()) + " weight sets");
  }
  for (std::size_t k = 0; k < prim.joints.size(); ++k) {
    if (prim.joints[k].size() != n) {
      return Fail(Ptr(Ptr(ptr, "joints"), k), "has " + std::to_string(prim.joints[k].size()) +
                                                  " entries, expected " + std::to_string(n) +
                                                  " (the vertex count)");
    }
    const std::string wptr = Ptr(Ptr(ptr, "weights"), k);
    if (!(s = CheckAttribute(*this, prim.weights[k], n, false, wptr)).ok()) return s;
    for (std::size_t v = 0; v < n; ++v) {
      for (int c = 0; c < 4; ++c) {
        if (prim.weights[k][v][c] < 0.0f) {
          return Fail(Ptr(Ptr(wptr, v), static_cast<std::size_t>(c)), "negative weight");
        }
      }
    }
  }
  for (std::size_t i = 0; i < prim.indices.size(); ++i) {
    if (prim.indices[i] >= n) {
      return Fail(Ptr(Ptr(ptr, "indices"), i), "index " + std::to_string(prim.indices[i]) +
                                                   " >= vertex count " + std::to_string(n));
    }
  }
  const std::size_t count = prim.indices.empty() ? n : prim.indices.size();
  bool fits = true;
  switch (prim.mode) {
    case PrimitiveMode::kPoints:
      break;
    case PrimitiveMode::kLines:
      fits = count % 2 == 0;
      break;
    case PrimitiveMode::kLineLoop:
    case PrimitiveMode::kLineStrip:
      fits = count == 0 || count >= 2;
      break;
    case PrimitiveMode::kTriangles:
      fits = count % 3 == 0;
      break;
    case PrimitiveMode::kTriangleStrip:
    case PrimitiveMode::kTriangleFan:
      fits = count == 0 || count >= 3;
      break;
  }
  if (!fits) {
    return Fail(Ptr(ptr, prim.indices.empty() ? "positions" : "indices"),
                std::to_string(count) + (prim.indices.empty() ? " vertices" : " indices") +
                    " do not fit mode " + ModeName(prim.mode));
  }
  for (std::size_t t = 0; t < prim.targets.size(); ++t) {
    const AssetMorphTarget& target = prim.targets[t];
    const std::string tptr = Ptr(Ptr(ptr, "targets"), t);
    if (!(s = CheckAttribute(*this, target.positions, n, true, Ptr(tptr, "positions"))).ok()) {
      return s;
    }
    if (!(s = CheckAttribute(*this, target.normals, n, true, Ptr(tptr, "normals"))).ok()) return s;
    if (!(s = CheckAttribute(*this, target.tangents, n, true, Ptr(tptr, "tangents"))).ok()) {
      return s;
    }
  }
  if (prim.targets.size() != asset_.meshes[m].primitives[0].targets.size()) {
    return Fail(Ptr(ptr, "targets"),
                std::to_string(prim.targets.size()) + " morph targets but primitive 0 has " +
                    std::to_string(asset_.meshes[m].primitives[0].targets.size()));
  }
  return CheckIndex(prim.material, asset_.materials.size(), true, Ptr(ptr, "material"), "material");
}

Status Checker::CheckMesh(std::size_t m) {
  const AssetMesh& mesh = asset_.meshes[m];
  const std::string ptr = Ptr(Ptr("", "meshes"), m);
  for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
    Status s = CheckPrimitive(m, p);
    if (!s.ok()) return s;
  }
  std::size_t bad = 0;
  if (!AllFinite(mesh.weights, &bad)) return Fail(Ptr(Ptr(ptr, "weights"), bad), "not finite");
  const std::size_t targets = mesh.primitives.empty() ? 0 : mesh.primitives[0].targets.size();
  if (!mesh.weights.empty() && mesh.weights.size() != targets) {
    return Fail(Ptr(ptr, "weights"), std::to_string(mesh.weights.size()) + " default weights but " +
                                         std::to_string(targets) + " morph targets");
  }
  return Status::Ok();
}

std::size_t TargetCount(const AssetMesh& mesh) {
  return mesh.primitives.empty() ? 0 : mesh.primitives[0].targets.size();
}

Status Checker::CheckNodes() {
  const std::size_t n = asset_.nodes.size();
  std::vector<Index> parent_of(n, kInvalidIndex);
  for (std::size_t i = 0; i < n; ++i) {
    const AssetNode& node = asset_.nodes[i];
    const std::string ptr = Ptr(Ptr("", "nodes"), i);
    for (std::size_t k = 0; k < node.children.size(); ++k) {
      const Index c = node.children[k];
      const std::string cptr = Ptr(Ptr(ptr, "children"), k);
      Status s = CheckIndex(c, n, false, cptr, "child node");
      if (!s.ok()) return s;
      if (static_cast<std::size_t>(c) == i) return Fail(cptr, "node is its own child");
      if (parent_of[c] != kInvalidIndex) {
        return Fail(cptr, "node " + std::to_string(c) + " has two parents (" +
                              std::to_string(parent_of[c]) + " and " + std::to_string(i) + ")");
      }
      parent_of[c] = static_cast<Index>(i);
    }
  }
  std::vector<Index> stack;
  std::vector<bool> reached(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    const AssetNode& node = asset_.nodes[i];
    const std::string ptr = Ptr(Ptr("", "nodes"), i);
    if (node.parent != parent_of[i]) {
      return Fail(Ptr(ptr, "parent"), "parent " + std::to_string(node.parent) +
                                          " disagrees with the children lists (" +
                                          std::to_string(parent_of[i]) + ")");
    }
    if (parent_of[i] == kInvalidIndex) stack.push_back(static_cast<Index>(i));
    Status s = CheckIndex(node.mesh, asset_.meshes.size(), true, Ptr(ptr, "mesh"), "mesh");
    if (!s.ok()) return s;
    s = CheckIndex(node.skin, asset_.skins.size(), true, Ptr(ptr, "skin"), "skin");
    if (!s.ok()) return s;
    if (!Finite(node.translation)) return Fail(Ptr(ptr, "translation"), "not finite");
    if (!Finite(node.rotation)) return Fail(Ptr(ptr, "rotation"), "not finite");
    if (node.rotation.x == 0.0 && node.rotation.y == 0.0 && node.rotation.z == 0.0 &&
        node.rotation.w == 0.0) {
      return Fail(Ptr(ptr, "rotation"), "zero quaternion");
    }
    if (!Finite(node.scale)) return Fail(Ptr(ptr, "scale"), "not finite");
    if (!Finite(node.matrix)) return Fail(Ptr(ptr, "matrix"), "not finite");
    std::size_t bad = 0;
    if (!AllFinite(node.weights, &bad)) {
      return Fail(Ptr(Ptr(ptr, "weights"), bad), "not finite");
    }
    if (node.mesh != kInvalidIndex && !node.weights.empty() &&
        node.weights.size() != TargetCount(asset_.meshes[node.mesh])) {
      return Fail(Ptr(ptr, "weights"), std::to_string(node.weights.size()) + " weights but mesh " +
                                           std::to_string(node.mesh) + " has " +
                                           std::to_string(TargetCount(asset_.meshes[node.mesh])) +
                                           " morph targets");
    }
  }
  // Every node has at most one parent, so the graph is a forest iff a walk down from the roots
  // reaches every node; the nodes left over lie on cycles.
  std::size_t reached_count = 0;
  while (!stack.empty()) {
    const Index i = stack.back();
    stack.pop_back();
    reached[i] = true;
    ++reached_count;
    for (Index c : asset_.nodes[i].children) stack.push_back(c);
  }
  if (reached_count != n) {
    for (std::size_t i = 0; i < n; ++i) {
      if (!reached[i]) return Fail(Ptr(Ptr("", "nodes"), i), "node is part of a cycle");
    }
  }
  return Status::Ok();
}

Status Checker::CheckSkin(std::size_t s) {
  const AssetSkin& skin = asset_.skins[s];
  const std::string ptr = Ptr(Ptr("", "skins"), s);
  for (std::size_t j = 0; j < skin.joints.size(); ++j) {
    Status st = CheckIndex(skin.joints[j], asset_.nodes.size(), false, Ptr(Ptr(ptr, "joints"), j),
                           "joint node");
    if (!st.ok()) return st;
  }
  Status st =
      CheckIndex(skin.skeleton, asset_.nodes.size(), true, Ptr(ptr, "skeleton"), "skeleton node");
  if (!st.ok()) return st;
  const std::size_t ibm_count = skin.inverse_bind_matrices.size();
  if (ibm_count != skin.joints.size() && (skin.has_inverse_bind_matrices || ibm_count != 0)) {
    return Fail(Ptr(ptr, "inverse_bind_matrices"), std::to_string(ibm_count) + " matrices for " +
                                                       std::to_string(skin.joints.size()) +
                                                       " joints");
  }
  for (std::size_t j = 0; j < ibm_count; ++j) {
    const glm::mat4& m = skin.inverse_bind_matrices[j];
    const std::string mptr = Ptr(Ptr(ptr, "inverse_bind_matrices"), j);
    if (!Finite(m)) return Fail(mptr, "not finite");
    if (std::fabs(m[0][3]) > 1e-6f || std::fabs(m[1][3]) > 1e-6f || std::fabs(m[2][3]) > 1e-6f ||
        std::fabs(m[3][3] - 1.0f) > 1e-6f) {
      return Fail(mptr, "last row is not (0, 0, 0, 1)");
    }
  }
  return Status::Ok();
}

int PathComponents(AnimationPath path, const Asset& asset, Index node) {
  switch (path) {
    case AnimationPath::kTranslation:
    case AnimationPath::kScale:
      return 3;
    case AnimationPath::kRotation:
      return 4;
    case AnimationPath::kWeights: {
      const Index mesh = asset.nodes[node].mesh;
      if (mesh == kInvalidIndex) return -1;  // Any count.
      return static_cast<int>(TargetCount(asset.meshes[mesh]));
    }
  }
  return -1;
}

Status Checker::CheckAnimation(std::size_t a) {
  const AssetAnimation& anim = asset_.animations[a];
  const std::string ptr = Ptr(Ptr("", "animations"), a);
  for (std::size_t k = 0; k < anim.samplers.size(); ++k) {
    const AssetAnimationSampler& sampler = anim.samplers[k];
    const std::string sptr = Ptr(Ptr(ptr, "samplers"), k);
    if (static_cast<unsigned>(sampler.interpolation) >
        static_cast<unsigned>(Interpolation::kCubicSpline)) {
      return Fail(Ptr(sptr, "interpolation"), "unknown interpolation");
    }
    if (sampler.times.empty()) return Fail(Ptr(sptr, "times"), "no keyframes");
    for (std::size_t i = 0; i < sampler.times.size(); ++i) {
      if (!Finite(sampler.times[i])) return Fail(Ptr(Ptr(sptr, "times"), i), "not finite");
      if (i > 0 && !(sampler.times[i] > sampler.times[i - 1])) {
        return Fail(Ptr(Ptr(sptr, "times"), i), "keyframe times not strictly increasing");
      }
    }
    if (sampler.components <= 0) {
      return Fail(Ptr(sptr, "components"),
                  "component count " + std::to_string(sampler.components) + " is not positive");
    }
    const std::size_t per_key = static_cast<std::size_t>(sampler.components) *
                                (sampler.interpolation == Interpolation::kCubicSpline ? 3u : 1u);
    if (sampler.values.size() % per_key != 0 ||
        sampler.values.size() / per_key != sampler.times.size()) {
      return Fail(Ptr(sptr, "values"), std::to_string(sampler.values.size()) +
                                           " values, expected " +
                                           std::to_string(sampler.times.size()) + " keyframes * " +
                                           std::to_string(per_key));
    }
    std::size_t bad = 0;
    if (!AllFinite(sampler.values, &bad)) {
      return Fail(Ptr(Ptr(sptr, "values"), bad), "not finite");
    }
  }
  for (std::size_t k = 0; k < anim.channels.size(); ++k) {
    const AssetAnimationChannel& channel = anim.channels[k];
    const std::string cptr = Ptr(Ptr(ptr, "channels"), k);
    Status s =
        CheckIndex(channel.sampler, anim.samplers.size(), false, Ptr(cptr, "sampler"), "sampler");
    if (!s.ok()) return s;
    s = CheckIndex(channel.node, asset_.nodes.size(), false, Ptr(cptr, "node"), "node");
    if (!s.ok()) return s;
    if (static_cast<unsigned>(channel.path) > static_cast<unsigned>(AnimationPath::kWeights)) {
      return Fail(Ptr(cptr, "path"), "unknown path");
    }
    const int expected = PathComponents(channel.path, asset_, channel.node);
    const int got = anim.samplers[channel.sampler].components;
    if (expected >= 0 && got != expected) {
      return Fail(Ptr(cptr, "sampler"), "sampler has " + std::to_string(got) +
                                            " components, the path needs " +
                                            std::to_string(expected));
    }
  }
  return Status::Ok();
}

Status Checker::Run() {
  Status s =
      CheckIndex(asset_.default_scene, asset_.scenes.size(), true, "/default_scene", "scene");
  if (!s.ok()) return s;
  for (std::size_t m = 0; m < asset_.meshes.size(); ++m) {
    if (!(s = CheckMesh(m)).ok()) return s;
  }
  for (std::size_t t = 0; t < asset_.textures.size(); ++t) {
    const std::string ptr = Ptr(Ptr("", "textures"), t);
    s = CheckIndex(asset_.textures[t].image, asset_.images.size(), true, Ptr(ptr, "image"),
                   "image");
    if (!s.ok()) return s;
    s = CheckIndex(asset_.textures[t].sampler, asset_.samplers.size(), true, Ptr(ptr, "sampler"),
                   "sampler");
    if (!s.ok()) return s;
  }
  if (!(s = CheckNodes()).ok()) return s;
  for (std::size_t k = 0; k < asset_.skins.size(); ++k) {
    if (!(s = CheckSkin(k)).ok()) return s;
  }
  // Joint indices against every skin a mesh is drawn with: the largest joint index of each mesh
  // is found once, so instancing costs nothing extra.
  struct MaxJoint {
    int value = -1;
    std::string pointer;
  };
  std::vector<MaxJoint> max_joint(asset_.meshes.size());
  std::vector<bool> scanned(asset_.meshes.size(), false);
  for (std::size_t i = 0; i < asset_.nodes.size(); ++i) {
    const AssetNode& node = asset_.nodes[i];
    if (node.mesh == kInvalidIndex || node.skin == kInvalidIndex) continue;
    MaxJoint& mj = max_joint[node.mesh];
    if (!scanned[node.mesh]) {
      scanned[node.mesh] = true;
      const AssetMesh& mesh = asset_.meshes[node.mesh];
      for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
        const AssetPrimitive& prim = mesh.primitives[p];
        for (std::size_t k = 0; k < prim.joints.size(); ++k) {
          for (std::size_t v = 0; v < prim.joints[k].size(); ++v) {
            for (int c = 0; c < 4; ++c) {
              if (int(prim.joints[k][v][c]) > mj.value) {
                mj.value = int(prim.joints[k][v][c]);
                mj.pointer = Ptr(
                    Ptr(Ptr(Ptr(Ptr(Ptr(Ptr("", "meshes"), std::size_t(node.mesh)), "primitives"),
                                p),
                            "joints"),
                        k),
                    v);
              }
            }
          }
        }
      }
    }
    const std::size_t joint_count = asset_.skins[node.skin].joints.size();
    if (mj.value >= 0 && static_cast<std::size_t>(mj.value) >= joint_count) {
      return Fail(mj.pointer, "joint index " + std::to_string(mj.value) + " >= joint count " +
                                  std::to_string(joint_count) + " of skin " +
                                  std::to_string(node.skin) + " used by node " + std::to_string(i));
    }
  }
  for (std::size_t a = 0; a < asset_.animations.size(); ++a) {
    if (!(s = CheckAnimation(a)).ok()) return s;
  }
  for (std::size_t k = 0; k < asset_.scenes.size(); ++k) {
    const AssetScene& scene = asset_.scenes[k];
    for (std::size_t r = 0; r < scene.nodes.size(); ++r) {
      const std::string ptr = Ptr(Ptr(Ptr(Ptr("", "scenes"), k), "nodes"), r);
      s = CheckIndex(scene.nodes[r], asset_.nodes.size(), false, ptr, "node");
      if (!s.ok()) return s;
      if (asset_.nodes[scene.nodes[r]].parent != kInvalidIndex) {
        return Fail(ptr, "node " + std::to_string(scene.nodes[r]) + " is not a root");
      }
    }
  }
  return Status::Ok();
}

}  // namespace

Status ValidateAsset(const Asset& asset) { return Checker(asset).Run(); }

}  // namespace dermis

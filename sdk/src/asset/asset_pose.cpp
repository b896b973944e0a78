// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/asset/asset_pose.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

namespace dermis {
namespace {

/// Reads one glTF quaternion (x, y, z, w) from `v` into glm's (w, x, y, z).
glm::dquat QuatFromXyzw(const double* v) { return glm::dquat(v[3], v[0], v[1], v[2]); }

glm::dquat NormalizeOrIdentity(const glm::dquat& q) {
  const double len = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (!(len > 0.0) || !std::isfinite(len)) return glm::dquat(1.0, 0.0, 0.0, 0.0);
  return glm::dquat(q.w / len, q.x / len, q.y / len, q.z / len);
}

/// Spherical linear interpolation along the shorter arc.
glm::dquat Slerp(glm::dquat a, glm::dquat b, double s) {
  double dot = a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
  if (dot < 0.0) {
    b = glm::dquat(-b.w, -b.x, -b.y, -b.z);
    dot = -dot;
  }
  double wa, wb;
  if (dot > 1.0 - 1e-9) {
    // Nearly parallel: sin(theta) ~ 0, a normalised lerp is exact to rounding.
    wa = 1.0 - s;
    wb = s;
  } else {
    const double theta = std::acos(dot);
    const double sin_theta = std::sin(theta);
    wa = std::sin((1.0 - s) * theta) / sin_theta;
    wb = std::sin(s * theta) / sin_theta;
  }
  return NormalizeOrIdentity(glm::dquat(wa * a.w + wb * b.w, wa * a.x + wb * b.x,
                                        wa * a.y + wb * b.y, wa * a.z + wb * b.z));
}

/// Samples `sampler` at `time` into out[0 .. components) (double precision).
void Sample(const AssetAnimationSampler& sampler, bool is_rotation, double time,
            std::vector<double>* out) {
  const std::size_t c = static_cast<std::size_t>(std::max(sampler.components, 0));
  const bool cubic = sampler.interpolation == Interpolation::kCubicSpline;
  const std::size_t stride = cubic ? 3 * c : c;
  const std::size_t value_offset = cubic ? c : 0;  // In-tangent, value, out-tangent.
  out->assign(c, 0.0);
  const std::vector<float>& times = sampler.times;
  const std::vector<float>& values = sampler.values;
  if (times.empty() || values.size() < times.size() * stride) return;
  auto value = [&](std::size_t key, std::size_t part, std::size_t i) {
    return static_cast<double>(values[key * stride + part + i]);
  };
  std::size_t key = 0;
  bool exact = false;
  if (!(time > double(times.front()))) {
    key = 0;
    exact = true;
  } else if (!(time < double(times.back()))) {
    key = times.size() - 1;
    exact = true;
  } else {
    // times[key] <= time < times[key + 1].
    const auto it = std::upper_bound(times.begin(), times.end(), time,
                                     [](double t, float k) { return t < double(k); });
    key = static_cast<std::size_t>(it - times.begin()) - 1;
    exact = sampler.interpolation == Interpolation::kStep;
  }
  if (exact) {
    for (std::size_t i = 0; i < c; ++i) (*out)[i] = value(key, value_offset, i);
    if (is_rotation && c == 4) {
      const glm::dquat q = NormalizeOrIdentity(QuatFromXyzw(out->data()));
      *out = {q.x, q.y, q.z, q.w};
    }
    return;
  }
  const double t0 = times[key], t1 = times[key + 1];
  const double dt = t1 - t0;
  const double s = (time - t0) / dt;
  if (sampler.interpolation == Interpolation::kLinear) {
    if (is_rotation && c == 4) {
      double a[4], b[4];
      for (std::size_t i = 0; i < 4; ++i) {
        a[i] = value(key, 0, i);
        b[i] = value(key + 1, 0, i);
      }
      const glm::dquat q = Slerp(QuatFromXyzw(a), QuatFromXyzw(b), s);
      *out = {q.x, q.y, q.z, q.w};
      return;
    }
    for (std::size_t i = 0; i < c; ++i) {
      (*out)[i] = (1.0 - s) * value(key, 0, i) + s * value(key + 1, 0, i);
    }
    return;
  }
  // CUBICSPLINE (glTF 2.0 appendix C): Hermite with tangents scaled by the keyframe delta.
  const double s2 = s * s, s3 = s2 * s;
  const double h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
  const double h10 = s3 - 2.0 * s2 + s;
  const double h01 = -2.0 * s3 + 3.0 * s2;
  const double h11 = s3 - s2;
  for (std::size_t i = 0; i < c; ++i) {
    const double v0 = value(key, c, i);      // Value of key k.
    const double b0 = value(key, 2 * c, i);  // Out-tangent of key k.
    const double v1 = value(key + 1, c, i);  // Value of key k+1.
    const double a1 = value(key + 1, 0, i);  // In-tangent of key k+1.
    (*out)[i] = h00 * v0 + h10 * dt * b0 + h01 * v1 + h11 * dt * a1;
  }
  if (is_rotation && c == 4) {
    const glm::dquat q = NormalizeOrIdentity(QuatFromXyzw(out->data()));
    *out = {q.x, q.y, q.z, q.w};
  }
}

/// The upper-left 3x3 cofactor matrix of `m` (= det * inverse transpose).
glm::dmat3 Cofactor3(const glm::dmat4& m) {
  const glm::dvec3 c0(m[0]), c1(m[1]), c2(m[2]);
  // Columns of the cofactor matrix: cross products of the other two columns.
  return glm::dmat3(glm::cross(c1, c2), glm::cross(c2, c0), glm::cross(c0, c1));
}

}  // namespace

glm::dmat4 NodeTransform::Matrix() const {
  if (has_matrix) return matrix;
  const glm::dquat q = rotation;
  const double xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
  const double xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
  const double wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
  glm::dmat4 m(1.0);
  // Column-major: m[c][r]. Rotation columns scaled by S, then translation.
  m[0] = glm::dvec4(1.0 - 2.0 * (yy + zz), 2.0 * (xy + wz), 2.0 * (xz - wy), 0.0) * scale.x;
  m[1] = glm::dvec4(2.0 * (xy - wz), 1.0 - 2.0 * (xx + zz), 2.0 * (yz + wx), 0.0) * scale.y;
  m[2] = glm::dvec4(2.0 * (xz + wy), 2.0 * (yz - wx), 1.0 - 2.0 * (xx + yy), 0.0) * scale.z;
  m[3] = glm::dvec4(translation, 1.0);
  return m;
}

void RestPose(const Asset& asset, AssetPose* pose) {
  pose->local.resize(asset.nodes.size());
  pose->morph_weights.resize(asset.nodes.size());
  for (std::size_t i = 0; i < asset.nodes.size(); ++i) {
    const AssetNode& node = asset.nodes[i];
    NodeTransform& t = pose->local[i];
    t.translation = node.translation;
    t.rotation = node.rotation;
    t.scale = node.scale;
    t.has_matrix = node.has_matrix;
    t.matrix = node.matrix;
    pose->morph_weights[i] = node.weights;
  }
}

void SamplePose(const Asset& asset, int animation, double time, AssetPose* pose) {
  RestPose(asset, pose);
  if (animation < 0 || static_cast<std::size_t>(animation) >= asset.animations.size()) return;
  const AssetAnimation& anim = asset.animations[animation];
  std::vector<double> v;
  for (const AssetAnimationChannel& channel : anim.channels) {
    if (channel.sampler < 0 || static_cast<std::size_t>(channel.sampler) >= anim.samplers.size() ||
        channel.node < 0 || static_cast<std::size_t>(channel.node) >= asset.nodes.size()) {
      continue;
    }
    const bool rotation = channel.path == AnimationPath::kRotation;
    Sample(anim.samplers[channel.sampler], rotation, time, &v);
    NodeTransform& t = pose->local[channel.node];
    switch (channel.path) {
      case AnimationPath::kTranslation:
        if (v.size() == 3) t.translation = glm::dvec3(v[0], v[1], v[2]);
        break;
      case AnimationPath::kRotation:
        if (v.size() == 4) t.rotation = QuatFromXyzw(v.data());
        break;
      case AnimationPath::kScale:
        if (v.size() == 3) t.scale = glm::dvec3(v[0], v[1], v[2]);
        break;
      case AnimationPath::kWeights:
        pose->morph_weights[channel.node] = v;
        break;
    }
  }
}

void ComputeWorldMatrices(const Asset& asset, const AssetPose& pose,
                          std::vector<glm::dmat4>* world) {
  const std::size_t n = asset.nodes.size();
  world->assign(n, glm::dmat4(1.0));
  std::vector<glm::dmat4> local(n, glm::dmat4(1.0));
  for (std::size_t i = 0; i < n && i < pose.local.size(); ++i) local[i] = pose.local[i].Matrix();
  // Walk down from the roots with an explicit stack, so that any node order works and deep
  // chains cannot overflow the call stack. Nodes not reached (only in invalid assets) keep
  // their local matrix.
  std::vector<bool> done(n, false);
  std::vector<Index> stack;
  for (std::size_t i = 0; i < n; ++i) {
    if (asset.nodes[i].parent == kInvalidIndex) stack.push_back(static_cast<Index>(i));
  }
  while (!stack.empty()) {
    const Index i = stack.back();
    stack.pop_back();
    if (done[i]) continue;
    done[i] = true;
    const Index p = asset.nodes[i].parent;
    (*world)[i] = p == kInvalidIndex ? local[i] : (*world)[p] * local[i];
    for (Index c : asset.nodes[i].children) {
      if (c >= 0 && static_cast<std::size_t>(c) < n && !done[c]) stack.push_back(c);
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!done[i]) (*world)[i] = local[i];
  }
}

void ComputeJointMatrices(const AssetSkin& skin, const std::vector<glm::dmat4>& world,
                          std::vector<glm::dmat4>* joint_matrices) {
  joint_matrices->assign(skin.joints.size(), glm::dmat4(1.0));
  for (std::size_t j = 0; j < skin.joints.size(); ++j) {
    const Index node = skin.joints[j];
    const glm::dmat4 w =
        node >= 0 && static_cast<std::size_t>(node) < world.size() ? world[node] : glm::dmat4(1.0);
    const glm::dmat4 ibm = j < skin.inverse_bind_matrices.size()
                               ? glm::dmat4(skin.inverse_bind_matrices[j])
                               : glm::dmat4(1.0);
    (*joint_matrices)[j] = w * ibm;
  }
}

void PosePrimitive(const Asset& asset, const AssetPose& pose, const std::vector<glm::dmat4>& world,
                   Index node, const AssetPrimitive& primitive, std::vector<glm::dvec3>* positions,
                   std::vector<glm::dvec3>* normals) {
  const std::size_t n = primitive.positions.size();
  const bool with_normals = normals != nullptr && primitive.normals.size() == n && n > 0;
  positions->resize(n);
  for (std::size_t v = 0; v < n; ++v) (*positions)[v] = glm::dvec3(primitive.positions[v]);
  if (normals != nullptr) {
    normals->clear();
    if (with_normals) {
      normals->resize(n);
      for (std::size_t v = 0; v < n; ++v) (*normals)[v] = glm::dvec3(primitive.normals[v]);
    }
  }
  const bool valid_node = node >= 0 && static_cast<std::size_t>(node) < asset.nodes.size();
  const AssetNode* asset_node = valid_node ? &asset.nodes[node] : nullptr;

  // Morph targets: the pose's weights for this node, else the mesh defaults.
  std::vector<double> weights;
  if (valid_node && static_cast<std::size_t>(node) < pose.morph_weights.size() &&
      !pose.morph_weights[node].empty()) {
    weights = pose.morph_weights[node];
  } else if (asset_node != nullptr && asset_node->mesh >= 0 &&
             static_cast<std::size_t>(asset_node->mesh) < asset.meshes.size()) {
    const std::vector<float>& w = asset.meshes[asset_node->mesh].weights;
    weights.assign(w.begin(), w.end());
  }
  for (std::size_t t = 0; t < primitive.targets.size() && t < weights.size(); ++t) {
    const double w = weights[t];
    if (w == 0.0) continue;
    const AssetMorphTarget& target = primitive.targets[t];
    if (target.positions.size() == n) {
      for (std::size_t v = 0; v < n; ++v) (*positions)[v] += w * glm::dvec3(target.positions[v]);
    }
    if (with_normals && target.normals.size() == n) {
      for (std::size_t v = 0; v < n; ++v) (*normals)[v] += w * glm::dvec3(target.normals[v]);
    }
  }

  const glm::dmat4 node_world =
      valid_node && static_cast<std::size_t>(node) < world.size() ? world[node] : glm::dmat4(1.0);
  const bool skinned = asset_node != nullptr && asset_node->skin >= 0 &&
                       static_cast<std::size_t>(asset_node->skin) < asset.skins.size();
  std::vector<glm::dmat4> joint_matrices;
  if (skinned) ComputeJointMatrices(asset.skins[asset_node->skin], world, &joint_matrices);

  const glm::dmat3 node_cofactor = Cofactor3(node_world);
  const double node_det = glm::determinant(glm::dmat3(node_world));
  for (std::size_t v = 0; v < n; ++v) {
    glm::dmat4 m = node_world;
    bool own = true;
    if (skinned) {
      glm::dmat4 blend(0.0);
      double total = 0.0;
      const std::size_t sets = std::min(primitive.joints.size(), primitive.weights.size());
      for (std::size_t k = 0; k < sets; ++k) {
        if (primitive.joints[k].size() != n || primitive.weights[k].size() != n) continue;
        for (int c = 0; c < 4; ++c) {
          const double w = primitive.weights[k][v][c];
          const std::size_t j = primitive.joints[k][v][c];
          if (w == 0.0 || j >= joint_matrices.size()) continue;
          blend += w * joint_matrices[j];
          total += w;
        }
      }
      // A vertex whose weights are all zero is not moved by the skin: it follows the node.
      if (total != 0.0) {
        m = blend;
        own = false;
      }
    }
    (*positions)[v] = glm::dvec3(m * glm::dvec4((*positions)[v], 1.0));
    if (with_normals) {
      const glm::dmat3 cof = own ? node_cofactor : Cofactor3(m);
      const double det = own ? node_det : glm::determinant(glm::dmat3(m));
      glm::dvec3 nrm = cof * (*normals)[v];
      if (det < 0.0) nrm = -nrm;  // Inverse transpose = cofactor / det.
      const double len = glm::length(nrm);
      (*normals)[v] = len > 0.0 ? nrm / len : glm::dvec3(0.0);
    }
  }
}

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Posing a fitted character offline ([Y] section 5, docs/notes/sweep.md section 1.7): the
// skeleton's pose deforms the control vertices, the patches are refitted
// (ManifoldDomain::FitPatches) and the displaced surface is evaluated with the unchanged
// displacements (paper Eq. 3-4) at the bound vertices or the tessellation samples. Plus the static
// asset of a pose and the morph-target bake of every clip.
#include "dermis/offline/character/character_pose.h"

#include <algorithm>
#include <cmath>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <map>
#include <utility>

#include "dermis/core/limits.h"
#include "dermis/core/parallel.h"
#include "dermis/offline/character/character_export.h"
#include "dermis/offline/character/skin_transfer.h"
#include "dermis/surface/surface_evaluator.h"
#include "offline/character/character_eval.h"

namespace dermis {
namespace {

/// The upper-left 3x3 cofactor matrix of `m` (= det * inverse transpose).
glm::dmat3 Cofactor3(const glm::dmat4& m) {
  const glm::dvec3 c0(m[0]), c1(m[1]), c2(m[2]);
  return glm::dmat3(glm::cross(c1, c2), glm::cross(c2, c0), glm::cross(c0, c1));
}

/// A normal moved by the linear part of `m` (inverse transpose, sign of the determinant kept so
/// that it keeps facing outward), unit length.
Vec3 TransformNormal(const glm::dmat4& m, const Vec3& n) {
  Vec3 r = Cofactor3(m) * n;
  if (glm::determinant(glm::dmat3(m)) < 0.0) r = -r;
  const double len = glm::length(r);
  return len > 0.0 ? r / len : n;
}

bool IsTriangleMode(PrimitiveMode mode) {
  return mode == PrimitiveMode::kTriangles || mode == PrimitiveMode::kTriangleStrip ||
         mode == PrimitiveMode::kTriangleFan;
}

std::string SkinPointer(Index skin) { return "/skins/" + std::to_string(skin); }

}  // namespace

std::vector<double> ClipStepTimes(double time, double steps_per_second) {
  std::vector<double> times;
  if (!(time > 0.0) || !(steps_per_second > 0.0) || !std::isfinite(time * steps_per_second)) {
    times.push_back(std::isfinite(time) && time > 0.0 ? time : 0.0);
    return times;
  }
  // At most 10 million steps (a longer history changes nothing the unwrapping needs).
  steps_per_second = std::min(steps_per_second, 1e7 / time);
  // A step closer to `time` than a thousandth of a step is merged into it, and so is one that
  // float32 (glTF keyframe times) could not tell apart from it.
  const double steps = std::ceil(time * steps_per_second - 1e-3);
  const auto k_end = static_cast<std::size_t>(std::max(0.0, steps));
  times.reserve(k_end + 1);
  for (std::size_t k = 0; k < k_end; ++k) {
    times.push_back(static_cast<double>(k) / steps_per_second);
  }
  while (!times.empty() && !(static_cast<float>(times.back()) < static_cast<float>(time))) {
    times.pop_back();
  }
  times.push_back(time);
  return times;
}

/// A part's control vertices deformed by one skin.
struct PartInstance {
  Index skin = kInvalidIndex;
  Index part = kInvalidIndex;
  std::unique_ptr<Deformer> deformer;
  std::vector<Vec3> control;
  std::vector<LocalPatch> patches;
};

struct CharacterPoser::State {
  const Character* character = nullptr;
  CharacterPoseOptions options;
  Asset asset;
  character::SurfaceSources sources;
  std::vector<character::PartEval> evals;  // rest patches, displacement, orientation per part
  std::vector<PartInstance> instances;
  std::vector<DrawnPrimitive> drawn;
  std::vector<std::vector<int>> instance_of;  // per drawn primitive, per part: instance or -1
  std::vector<Index> skins_used;
  std::vector<std::vector<glm::dmat4>> skin_matrices;  // per skin of the asset
  AssetPose pose;
  std::vector<glm::dmat4> world;
  bool posed = false;
};

CharacterPoser::CharacterPoser() : state_(std::make_unique<State>()) {}
CharacterPoser::~CharacterPoser() = default;
CharacterPoser::CharacterPoser(CharacterPoser&&) noexcept = default;
CharacterPoser& CharacterPoser::operator=(CharacterPoser&&) noexcept = default;

const Asset& CharacterPoser::asset() const { return state_->asset; }
const std::vector<DrawnPrimitive>& CharacterPoser::drawn() const { return state_->drawn; }
const CharacterPoseOptions& CharacterPoser::options() const { return state_->options; }
const std::vector<VertexBinding>& CharacterPoser::surface_locations(std::size_t drawn_index) const {
  static const std::vector<VertexBinding> kNone;
  const State& st = *state_;
  if (drawn_index >= st.drawn.size()) return kNone;
  const DrawnPrimitive& dp = st.drawn[drawn_index];
  const auto m = static_cast<std::size_t>(dp.mesh);
  const auto p = static_cast<std::size_t>(dp.primitive);
  if (dp.mesh < 0 || m >= st.sources.size() || dp.primitive < 0 || p >= st.sources[m].size())
    return kNone;
  return st.sources[m][p];
}

namespace {

// The asset the poser draws (the bound asset, or the lod tessellation) and, per mesh,
// primitive and vertex, where the vertex sits on which part (empty for primitives no part
// draws).
Status PosedAssetAndSources(const Character& ch, const CharacterPoseOptions& options, Asset* asset,
                            character::SurfaceSources* sources) {
  CharacterExportOptions export_options;
  export_options.level = options.level;
  export_options.displacement_levels = options.displacement_levels;
  if (options.mode == CharacterPoseMode::kBound) {
    const Status s = BuildBoundAsset(ch, export_options, asset);
    if (!s.ok()) return s;
    *sources = ch.bindings;
    for (auto& mesh : *sources) {
      for (auto& prim : mesh) {
        bool any = false;
        for (const VertexBinding& b : prim) any = any || b.part != kInvalidIndex;
        if (!any) prim.clear();
      }
    }
    return Status::Ok();
  }
  if (options.mode == CharacterPoseMode::kLod) {
    return character::BuildLodAssetWithSources(ch, export_options, asset, nullptr, sources);
  }
  return Status::InvalidInput(ch.asset.source + ": unknown pose mode");
}

// The parts each mesh's primitives evaluate, in the order they first appear.
std::vector<std::vector<Index>> PartsOfMeshes(const Character& ch, const Asset& a,
                                              const character::SurfaceSources& sources) {
  std::vector<std::vector<Index>> parts_of_mesh(a.meshes.size());
  for (std::size_t m = 0; m < a.meshes.size() && m < sources.size(); ++m) {
    std::vector<bool> seen(ch.parts.size(), false);
    for (const auto& prim : sources[m]) {
      for (const VertexBinding& b : prim) {
        if (b.part < 0 || static_cast<std::size_t>(b.part) >= ch.parts.size()) continue;
        if (!seen[static_cast<std::size_t>(b.part)]) {
          seen[static_cast<std::size_t>(b.part)] = true;
          parts_of_mesh[m].push_back(b.part);
        }
      }
    }
  }
  return parts_of_mesh;
}

// The deformer of part k's control vertices by `rig` (skin `skin`), with the part's control
// weights.
Status MakePartInstance(const Character& ch, Index k, Index skin, const SkinRig& rig,
                        DeformerKind kind, PartInstance* inst) {
  const std::string& source = ch.asset.source;
  const CharacterPart& part = ch.parts[static_cast<std::size_t>(k)];
  const std::size_t n = part.surface.rest_positions.size();
  if (part.control_joints.size() != n || part.control_weights.size() != n) {
    return Status::InvalidInput(source + ": part " + std::to_string(k) +
                                ": control weights do not match its control vertices");
  }
  std::vector<VertexWeights> influences(n);
  for (std::size_t v = 0; v < n; ++v) {
    influences[v].joints = part.control_joints[v];
    influences[v].weights = part.control_weights[v];
  }
  inst->skin = skin;
  inst->part = k;
  const Status s = MakeDeformer(kind, rig, part.surface.rest_positions.data(), nullptr,
                                influences.data(), n, &inst->deformer);
  if (s.code() == StatusCode::kUnsupported) {
    return Status::Unsupported(source + ": the " + DeformerName(kind) +
                               " deformer is not available (" + s.message() + ")");
  }
  if (!s.ok()) {
    return s.WithContext(source + ": " + SkinPointer(skin) + ", part " + std::to_string(k) +
                         " (mesh " + std::to_string(part.mesh) + ")");
  }
  inst->control.resize(n);
  inst->patches.resize(n);
  return Status::Ok();
}

}  // namespace

Status CharacterPoser::Build(const Character& ch, const CharacterPoseOptions& options,
                             CharacterPoser* out) {
  if (Status s = character::RequireSourceAsset(ch); !s.ok()) return s;
  auto st = std::make_unique<State>();
  st->character = &ch;
  st->options = options;
  if (FindDeformer(options.deformer) == nullptr) {
    return Status::InvalidInput(ch.asset.source + ": unknown deformer " +
                                std::to_string(static_cast<unsigned>(options.deformer)));
  }
  Status s = PosedAssetAndSources(ch, options, &st->asset, &st->sources);
  if (!s.ok()) return s;
  st->evals.resize(ch.parts.size());
  for (std::size_t k = 0; k < ch.parts.size(); ++k) {
    s = character::MakePartEval(ch, static_cast<Index>(k), options.displacement_levels,
                                &st->evals[k]);
    if (!s.ok()) return s;
  }
  const Asset& a = st->asset;
  const std::vector<std::vector<Index>> parts_of_mesh = PartsOfMeshes(ch, a, st->sources);
  // Drawn primitives and one deformer per (skin, part).
  std::map<std::pair<Index, Index>, int> instance_index;
  std::map<Index, SkinRig> rigs;
  for (std::size_t node = 0; node < a.nodes.size(); ++node) {
    const Index mesh = a.nodes[node].mesh;
    if (mesh < 0 || static_cast<std::size_t>(mesh) >= a.meshes.size()) continue;
    const Index skin = a.nodes[node].skin;
    std::vector<int> part_instance(ch.parts.size(), -1);
    for (const Index k : parts_of_mesh[static_cast<std::size_t>(mesh)]) {
      const CharacterPart& part = ch.parts[static_cast<std::size_t>(k)];
      if (skin < 0 || part.control_weights.empty()) continue;  // static: the node's matrix
      const auto key = std::make_pair(skin, k);
      auto it = instance_index.find(key);
      if (it == instance_index.end()) {
        auto rig = rigs.find(skin);
        if (rig == rigs.end()) {
          SkinRig r;
          s = MakeSkinRig(a, skin, &r);
          if (!s.ok()) return s;
          rig = rigs.emplace(skin, std::move(r)).first;
        }
        PartInstance inst;
        s = MakePartInstance(ch, k, skin, rig->second, options.deformer, &inst);
        if (!s.ok()) return s;
        it = instance_index.emplace(key, static_cast<int>(st->instances.size())).first;
        st->instances.push_back(std::move(inst));
        if (std::find(st->skins_used.begin(), st->skins_used.end(), skin) == st->skins_used.end()) {
          st->skins_used.push_back(skin);
        }
      }
      part_instance[static_cast<std::size_t>(k)] = it->second;
    }
    const auto& prims = a.meshes[static_cast<std::size_t>(mesh)].primitives;
    for (std::size_t p = 0; p < prims.size(); ++p) {
      st->drawn.push_back({static_cast<Index>(node), mesh, static_cast<Index>(p)});
      st->instance_of.push_back(part_instance);
    }
  }
  st->skin_matrices.resize(a.skins.size());
  out->state_ = std::move(st);
  return Status::Ok();
}

Status CharacterPoser::SetPose(const AssetPose& pose) {
  State& st = *state_;
  st.pose = pose;
  ComputeWorldMatrices(st.asset, st.pose, &st.world);
  for (const Index skin : st.skins_used) {
    ComputeJointMatrices(st.asset.skins[static_cast<std::size_t>(skin)], st.world,
                         &st.skin_matrices[static_cast<std::size_t>(skin)]);
  }
  for (PartInstance& inst : st.instances) {
    const Status s =
        inst.deformer->SetPose(st.skin_matrices[static_cast<std::size_t>(inst.skin)].data());
    if (!s.ok()) {
      st.posed = false;
      return s.WithContext(st.asset.source + ": " + SkinPointer(inst.skin));
    }
  }
  st.posed = true;
  return Status::Ok();
}

void CharacterPoser::ResetHistory() {
  for (PartInstance& inst : state_->instances) inst.deformer->ResetHistory();
}

Status CharacterPoser::Evaluate(std::vector<PosedPrimitive>* out) {
  State& st = *state_;
  if (!st.posed) return Status::InvalidInput(st.asset.source + ": no pose was set");
  const Character& ch = *st.character;
  const int threads = ResolveThreadCount(st.options.threads);
  // Deform the control vertices of every (skin, part) and refit its patches.
  ParallelFor(threads, st.instances.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      PartInstance& inst = st.instances[i];
      inst.deformer->Deform(0, inst.control.size(), inst.control.data(), nullptr);
      ch.parts[static_cast<std::size_t>(inst.part)].surface.domain->FitPatches(inst.control.data(),
                                                                               inst.patches.data());
    }
  });
  out->resize(st.drawn.size());
  std::vector<std::string> errors(st.drawn.size());
  ParallelFor(threads, st.drawn.size(), [&](std::size_t begin, std::size_t end) {
    std::vector<glm::dvec3> x, nrm;
    for (std::size_t d = begin; d < end; ++d) {
      const DrawnPrimitive& dp = st.drawn[d];
      const AssetPrimitive& prim = st.asset.meshes[static_cast<std::size_t>(dp.mesh)]
                                       .primitives[static_cast<std::size_t>(dp.primitive)];
      // What a glTF viewer draws (skinning or the node's matrix, morph targets first) ...
      PosePrimitive(st.asset, st.pose, st.world, dp.node, prim, &x, &nrm);
      PosedPrimitive& o = (*out)[d];
      o.positions.assign(x.begin(), x.end());
      o.normals.assign(nrm.begin(), nrm.end());
      const bool want_normals = IsTriangleMode(prim.mode);
      if (want_normals && o.normals.size() != o.positions.size()) o.normals.clear();
      // ... replaced on the surfaces by the posed displaced surface.
      const std::vector<VertexBinding>* src = &surface_locations(d);
      if (!src->empty()) {
        if (want_normals && o.normals.empty()) o.normals.assign(o.positions.size(), Vec3(0, 0, 1));
        const glm::dmat4& node_world = st.world[static_cast<std::size_t>(dp.node)];
        const std::vector<int>& inst_of = st.instance_of[d];
        for (std::size_t v = 0; v < src->size() && v < o.positions.size(); ++v) {
          const VertexBinding& b = (*src)[v];
          if (b.part < 0) continue;
          const std::size_t k = static_cast<std::size_t>(b.part);
          const int i = inst_of[k];
          const character::PartEval& e = st.evals[k];
          const LocalPatch* patches =
              i >= 0 ? st.instances[static_cast<std::size_t>(i)].patches.data() : e.patches.data();
          SurfacePoint sp;
          if (!EvaluateSurface(*ch.parts[k].surface.domain, patches, e.displacement, b.face,
                               Vec2(b.u, b.v), &sp)) {
            errors[d] = st.asset.source + ": mesh " + std::to_string(dp.mesh) + " primitive " +
                        std::to_string(dp.primitive) + " vertex " + std::to_string(v) +
                        ": invalid surface location";
            break;
          }
          Vec3 n = sp.normal * e.orientation;
          if (i >= 0) {
            o.positions[v] = sp.position;
          } else {
            o.positions[v] = Vec3(node_world * glm::dvec4(sp.position, 1.0));
            n = TransformNormal(node_world, n);
          }
          if (want_normals) {
            const double len = glm::length(n);
            o.normals[v] = len > 0.0 ? n / len : Vec3(0.0, 0.0, 1.0);
          }
        }
      }
      if (want_normals && o.normals.empty())
        o.normals = character::TriangleNormals(prim, o.positions);
      if (!want_normals) o.normals.clear();
    }
  });
  for (const std::string& e : errors) {
    if (!e.empty()) return Status::InvalidInput(e);
  }
  return Status::Ok();
}

Status CharacterPoser::PoseClip(int clip, double time, double steps_per_second,
                                std::vector<PosedPrimitive>* out,
                                const ProgressCallback& progress) {
  State& st = *state_;
  ResetHistory();
  AssetPose pose;
  if (clip < 0) {
    RestPose(st.asset, &pose);
    const Status s = SetPose(pose);
    if (!s.ok()) return s;
    return Evaluate(out);
  }
  if (static_cast<std::size_t>(clip) >= st.asset.animations.size()) {
    return Status::InvalidInput(st.asset.source + ": clip " + std::to_string(clip) +
                                " does not exist (" + std::to_string(st.asset.animations.size()) +
                                " clips)");
  }
  if (!std::isfinite(time) || time < 0.0) {
    return Status::InvalidInput(st.asset.source + ": time must be finite and >= 0");
  }
  if (!std::isfinite(steps_per_second) || !(steps_per_second > 0.0)) {
    return Status::InvalidInput(st.asset.source + ": steps per second must be positive");
  }
  // Past the clip's end every pose is its last: the history needs the clip's steps only.
  const double duration = st.asset.animations[static_cast<std::size_t>(clip)].Duration();
  std::vector<double> steps = ClipStepTimes(std::min(time, duration), steps_per_second);
  if (time > duration) steps.push_back(time);
  const std::size_t work = steps.size() + 1;  // the steps, then the evaluation
  for (std::size_t i = 0; i < steps.size(); ++i) {
    ReportProgress(progress, "posing steps", i, work);
    SamplePose(st.asset, clip, steps[i], &pose);
    const Status s = SetPose(pose);
    if (!s.ok()) {
      return s.WithContext("clip " + std::to_string(clip) + " at " + std::to_string(steps[i]));
    }
  }
  ReportProgress(progress, "posing steps", steps.size(), work);
  const Status s = Evaluate(out);
  ReportProgress(progress, "posing steps", work, work);
  return s;
}

Status BuildPosedAsset(const CharacterPoser& poser, const std::vector<PosedPrimitive>& posed,
                       Asset* out) {
  const Asset& src = poser.asset();
  const std::vector<DrawnPrimitive>& drawn = poser.drawn();
  if (posed.size() != drawn.size()) {
    return Status::InvalidInput(src.source + ": " + std::to_string(posed.size()) +
                                " posed primitives for " + std::to_string(drawn.size()) +
                                " drawn ones");
  }
  Asset a;
  a.source = src.source;
  a.generator = src.generator;
  a.copyright = src.copyright;
  a.materials = src.materials;
  a.textures = src.textures;
  a.images = src.images;
  a.samplers = src.samplers;
  AssetScene scene;
  scene.name = "posed";
  for (std::size_t d = 0; d < drawn.size(); ++d) {
    const DrawnPrimitive& dp = drawn[d];
    if (d == 0 || drawn[d - 1].node != dp.node) {
      const AssetNode& node = src.nodes[static_cast<std::size_t>(dp.node)];
      AssetMesh mesh;
      mesh.name = src.meshes[static_cast<std::size_t>(dp.mesh)].name;
      a.meshes.push_back(std::move(mesh));
      AssetNode baked;
      baked.name = node.name.empty() ? "node " + std::to_string(dp.node) : node.name;
      baked.mesh = static_cast<Index>(a.meshes.size() - 1);
      a.nodes.push_back(std::move(baked));
      scene.nodes.push_back(static_cast<Index>(a.nodes.size() - 1));
    }
    const AssetPrimitive& sp = src.meshes[static_cast<std::size_t>(dp.mesh)]
                                   .primitives[static_cast<std::size_t>(dp.primitive)];
    const PosedPrimitive& pp = posed[d];
    if (pp.positions.size() != sp.positions.size() ||
        (!pp.normals.empty() && pp.normals.size() != pp.positions.size())) {
      return Status::InvalidInput(src.source + ": posed primitive " + std::to_string(d) +
                                  " does not match its source's vertex count");
    }
    AssetPrimitive p;
    p.mode = sp.mode;
    p.indices = sp.indices;
    p.texcoords = sp.texcoords;
    p.colors = sp.colors;
    p.material = sp.material;
    p.positions.resize(pp.positions.size());
    for (std::size_t v = 0; v < pp.positions.size(); ++v) {
      p.positions[v] = glm::vec3(pp.positions[v]);
    }
    p.normals.resize(pp.normals.size());
    for (std::size_t v = 0; v < pp.normals.size(); ++v) {
      // A zero normal (a zero NORMAL in the source, or a collapsed skinning matrix) cannot be
      // normalised; glTF needs unit normals.
      const glm::vec3 n(pp.normals[v]);
      const float len = glm::length(n);
      p.normals[v] = len > 0.0f && std::isfinite(len) ? n / len : glm::vec3(0.0f, 0.0f, 1.0f);
    }
    a.meshes.back().primitives.push_back(std::move(p));
  }
  a.scenes.push_back(std::move(scene));
  a.default_scene = 0;
  *out = std::move(a);
  return Status::Ok();
}

Status BuildBakedAsset(CharacterPoser* poser, double fps, Asset* out, CharacterBakeReport* report,
                       const ProgressCallback& progress) {
  const Asset& src = poser->asset();
  if (!std::isfinite(fps) || !(fps > 0.0)) {
    return Status::InvalidInput(src.source + ": frames per second must be positive");
  }
  if (src.animations.empty()) {
    return Status::InvalidInput(src.source + ": has no clips to bake");
  }
  std::vector<PosedPrimitive> rest;
  Status s = poser->PoseClip(-1, 0.0, fps, &rest);
  if (!s.ok()) return s;
  Asset a;
  s = BuildPosedAsset(*poser, rest, &a);
  if (!s.ok()) return s;
  const std::vector<DrawnPrimitive>& drawn = poser->drawn();
  // Which baked mesh and primitive each drawn primitive became (BuildPosedAsset's grouping).
  std::vector<std::pair<std::size_t, std::size_t>> target_of(drawn.size());
  for (std::size_t d = 0, mesh = 0, prim = 0; d < drawn.size(); ++d) {
    if (d > 0 && drawn[d - 1].node != drawn[d].node) ++mesh, prim = 0;
    target_of[d] = {mesh, prim++};
  }
  // The budget before any frame is listed or posed: frames (counted from the clip lengths) times
  // the vertices of the rest pose, against limits::kMaxBakedVertexFrames.
  {
    std::uint64_t vertices = 0;
    double frames = 0.0;
    for (const PosedPrimitive& p : rest) vertices += p.positions.size();
    for (const AssetAnimation& clip : src.animations) {
      const double d = clip.Duration();
      // As many as ClipStepTimes lists (it caps a clip at 1e7 steps).
      frames +=
          (std::isfinite(d) && d > 0.0 ? std::ceil(d * std::min(fps, 1e7 / d) - 1e-3) : 0.0) + 1.0;
    }
    const double vertex_frames = frames * static_cast<double>(std::max<std::uint64_t>(vertices, 1));
    if (!(vertex_frames <= static_cast<double>(limits::kMaxBakedVertexFrames))) {
      return Status::InvalidInput(
          src.source + ": baking " + std::to_string(static_cast<unsigned long long>(frames)) +
          " frames of " + std::to_string(vertices) + " vertices passes the limit of " +
          std::to_string(limits::kMaxBakedVertexFrames) +
          " vertex-frames (a clip too long for the frame rate: lower --fps or shorten the clips)");
    }
  }
  CharacterBakeReport rep;
  std::vector<std::vector<double>> frame_times(src.animations.size());
  for (std::size_t c = 0; c < src.animations.size(); ++c) {
    frame_times[c] = ClipStepTimes(src.animations[c].Duration(), fps);
    rep.frames.push_back(frame_times[c].size());
    rep.targets += frame_times[c].size();
  }
  for (const PosedPrimitive& p : rest) rep.vertices += p.positions.size();
  rep.vertex_frames = static_cast<std::uint64_t>(rep.vertices) * rep.targets;
  for (AssetMesh& m : a.meshes) {
    for (AssetPrimitive& p : m.primitives) p.targets.reserve(rep.targets);
  }
  std::vector<PosedPrimitive> frame;
  AssetPose pose;
  std::size_t baked = 0;
  for (std::size_t c = 0; c < src.animations.size(); ++c) {
    poser->ResetHistory();
    for (const double t : frame_times[c]) {
      ReportProgress(progress, "baking frames", baked++, rep.targets);
      SamplePose(src, static_cast<int>(c), t, &pose);
      s = poser->SetPose(pose);
      if (!s.ok()) return s.WithContext("clip " + std::to_string(c) + " at " + std::to_string(t));
      s = poser->Evaluate(&frame);
      if (!s.ok()) return s;
      for (std::size_t d = 0; d < drawn.size(); ++d) {
        AssetMorphTarget target;
        const PosedPrimitive& f = frame[d];
        const PosedPrimitive& r = rest[d];
        target.positions.resize(f.positions.size());
        for (std::size_t v = 0; v < f.positions.size(); ++v) {
          target.positions[v] = glm::vec3(f.positions[v] - r.positions[v]);
        }
        if (!r.normals.empty()) {
          target.normals.resize(f.normals.size());
          for (std::size_t v = 0; v < f.normals.size(); ++v) {
            target.normals[v] = glm::vec3(f.normals[v] - r.normals[v]);
          }
        }
        a.meshes[target_of[d].first].primitives[target_of[d].second].targets.push_back(
            std::move(target));
      }
    }
  }
  // One animation per clip: a LINEAR weights sampler, one-hot at the clip's frames, driving
  // every baked node.
  std::size_t first = 0;
  for (std::size_t c = 0; c < src.animations.size(); ++c) {
    AssetAnimation anim;
    anim.name = src.animations[c].name;
    AssetAnimationSampler sampler;
    sampler.interpolation = Interpolation::kLinear;
    sampler.components = static_cast<int>(rep.targets);
    const std::size_t frames = frame_times[c].size();
    sampler.times.resize(frames);
    sampler.values.assign(frames * rep.targets, 0.0f);
    for (std::size_t k = 0; k < frames; ++k) {
      sampler.times[k] = static_cast<float>(frame_times[c][k]);
      sampler.values[k * rep.targets + first + k] = 1.0f;
    }
    first += frames;
    anim.samplers.push_back(std::move(sampler));
    for (std::size_t n = 0; n < a.nodes.size(); ++n) {
      AssetAnimationChannel channel;
      channel.sampler = 0;
      channel.node = static_cast<Index>(n);
      channel.path = AnimationPath::kWeights;
      anim.channels.push_back(channel);
    }
    a.animations.push_back(std::move(anim));
  }
  ReportProgress(progress, "baking frames", rep.targets, rep.targets);
  *out = std::move(a);
  if (report != nullptr) *report = std::move(rep);
  return Status::Ok();
}

}  // namespace dermis

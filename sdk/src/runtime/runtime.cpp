// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The engine runtime: loading, outputs and the per-frame jobs (paper section 5: only the
// control vertices are deformed, the local patches are refitted by Eq. 2 and the unchanged
// displacements ride along; evaluation of Eq. 3-4 through an EvaluationPlan).
#include "dermis/runtime/runtime.h"

#include <algorithm>
#include <cmath>

#include "dermis/surface/bspline_displacement.h"
#include "runtime/tangent_frames.h"

namespace dermis {

struct RuntimeInstance::PartState {
  std::unique_ptr<Deformer> deformer;  // null for a static part
  std::vector<glm::dmat4> palette;
  std::vector<Vec3> control;
  std::vector<LocalPatch> patches;
  std::vector<float> packed;
};

RuntimeCharacter::~RuntimeCharacter() = default;
RuntimeOutput::~RuntimeOutput() = default;
RuntimeInstance::~RuntimeInstance() = default;

Status RuntimeCharacter::Load(const std::string& path, std::unique_ptr<RuntimeCharacter>* out) {
  Character c;
  const Status s = ReadCharacter(path, &c);
  if (!s.ok()) return s;
  return FromCharacter(std::move(c), out);
}

Status RuntimeCharacter::FromBytes(std::string_view bytes, const std::string& name,
                                   std::unique_ptr<RuntimeCharacter>* out) {
  Character c;
  const Status s = ParseCharacter(bytes, name, &c);
  if (!s.ok()) return s;
  return FromCharacter(std::move(c), out);
}

Status RuntimeCharacter::FromCharacter(Character character,
                                       std::unique_ptr<RuntimeCharacter>* out) {
  std::unique_ptr<RuntimeCharacter> r(new RuntimeCharacter());
  r->character_ = std::move(character);
  const Character& c = r->character_;
  const std::string& name = c.asset.source;
  r->rigs_.resize(c.asset.skins.size());
  r->rig_ok_.assign(c.asset.skins.size(), false);
  for (std::size_t p = 0; p < c.parts.size(); ++p) {
    const CharacterPart& part = c.parts[p];
    if (!part.surface.domain)
      return Status::InvalidInput(name + ": part " + std::to_string(p) + " has no surface");
    const std::size_t n = static_cast<std::size_t>(part.surface.domain->num_vertices());
    if (part.surface.rest_positions.size() != n) {
      return Status::InvalidInput(name + ": part " + std::to_string(p) +
                                  ": control vertex count disagrees with its domain");
    }
    if (part.skin == kInvalidIndex) continue;
    if (part.skin < 0 || static_cast<std::size_t>(part.skin) >= c.asset.skins.size()) {
      return Status::InvalidInput(name + ": part " + std::to_string(p) + ": skin " +
                                  std::to_string(part.skin) + " does not exist");
    }
    if (part.control_joints.size() != n || part.control_weights.size() != n) {
      return Status::InvalidInput(name + ": part " + std::to_string(p) +
                                  ": control-vertex influences missing");
    }
    const std::size_t s = static_cast<std::size_t>(part.skin);
    if (!r->rig_ok_[s]) {
      const Status st = MakeSkinRig(c.asset, part.skin, &r->rigs_[s]);
      if (!st.ok()) return st;
      r->rig_ok_[s] = true;
    }
  }
  r->bound_.resize(c.parts.size());
  r->locations_.resize(c.parts.size());
  for (std::size_t m = 0; m < c.bindings.size(); ++m) {
    for (std::size_t q = 0; q < c.bindings[m].size(); ++q) {
      for (std::size_t v = 0; v < c.bindings[m][q].size(); ++v) {
        const VertexBinding& b = c.bindings[m][q][v];
        if (b.part == kInvalidIndex) continue;
        if (b.part < 0 || static_cast<std::size_t>(b.part) >= c.parts.size()) {
          return Status::InvalidInput(name + ": a vertex binding names part " +
                                      std::to_string(b.part) + ", which does not exist");
        }
        const std::size_t p = static_cast<std::size_t>(b.part);
        r->bound_[p].push_back(
            BoundVertexRef{static_cast<Index>(m), static_cast<Index>(q), static_cast<Index>(v)});
        r->locations_[p].push_back(SampleLocation{b.face, b.u, b.v});
      }
    }
  }
  *out = std::move(r);
  return Status::Ok();
}

std::size_t RuntimeCharacter::num_control_vertices(std::size_t p) const {
  return p < num_parts() ? character_.parts[p].surface.rest_positions.size() : 0;
}

const SkinRig* RuntimeCharacter::rig(std::size_t p) const {
  if (p >= num_parts() || character_.parts[p].skin == kInvalidIndex) return nullptr;
  return &rigs_[static_cast<std::size_t>(character_.parts[p].skin)];
}

std::size_t RuntimeCharacter::num_joints(std::size_t p) const {
  const SkinRig* r = rig(p);
  return r ? r->parents.size() : 0;
}

const std::vector<BoundVertexRef>& RuntimeCharacter::bound_vertices(std::size_t p) const {
  static const std::vector<BoundVertexRef> kNone;
  return p < num_parts() ? bound_[p] : kNone;
}

const std::vector<SampleLocation>& RuntimeCharacter::bound_locations(std::size_t p) const {
  static const std::vector<SampleLocation> kNone;
  return p < num_parts() ? locations_[p] : kNone;
}

Status RuntimeOutput::Build(const RuntimeCharacter& character, std::size_t part,
                            const OutputSpec& spec, std::unique_ptr<RuntimeOutput>* out) {
  const std::string& name = character.character().asset.source;
  if (part >= character.num_parts()) {
    return Status::InvalidInput(name + ": part " + std::to_string(part) + " does not exist");
  }
  if (spec.kind == OutputKind::kLevel && (spec.level < 1 || spec.level > 64)) {
    return Status::InvalidInput("output level must be in 1..64, got " + std::to_string(spec.level));
  }
  if (spec.displacement_levels < -1) {
    return Status::InvalidInput("displacement levels must be -1 (all) or >= 0");
  }
  const DisplacedSurface& surface = character.character().parts[part].surface;
  std::unique_ptr<RuntimeOutput> r(new RuntimeOutput());
  r->character_ = &character;
  r->part_ = part;
  r->spec_ = spec;
  const Displacement* disp = nullptr;
  std::unique_ptr<TruncatedDisplacement> truncated;
  if (surface.displacement && spec.displacement_levels != 0) {
    disp = surface.displacement.get();
    if (spec.displacement_levels > 0) {
      truncated.reset(
          new TruncatedDisplacement(surface.displacement.get(), spec.displacement_levels));
      disp = truncated.get();
    }
  }
  EvaluationPlanOptions po;
  po.threads = spec.threads;
  Status s;
  if (spec.kind == OutputKind::kLevel) {
    TessellationPattern pattern;
    s = TessellationPattern::Build(surface.domain->topology(), spec.level, &pattern);
    if (!s.ok()) return s;
    s = EvaluationPlan::Build(*surface.domain, disp, pattern.samples.data(), pattern.samples.size(),
                              po, &r->plan_);
    r->triangles_ = std::move(pattern.triangles);
  } else {
    const std::vector<SampleLocation>& loc = character.bound_locations(part);
    s = EvaluationPlan::Build(*surface.domain, disp, loc.data(), loc.size(), po, &r->plan_);
  }
  if (!s.ok()) return s.WithContext(name + ", part " + std::to_string(part));
  if (spec.tangents) {
    if (spec.kind != OutputKind::kBound) {
      return Status::InvalidInput(name + ", part " + std::to_string(part) +
                                  ": tangents need a bound output (a tessellation level has no "
                                  "texture coordinates)");
    }
    s = BuildTangentFrames(character, part, r->plan_, &r->tangent_frames_);
    if (!s.ok()) return s;
  }
  *out = std::move(r);
  return Status::Ok();
}

Status RuntimeInstance::Create(const RuntimeCharacter& character, DeformerKind deformer,
                               std::unique_ptr<RuntimeInstance>* out) {
  std::unique_ptr<RuntimeInstance> r(new RuntimeInstance());
  r->character_ = &character;
  r->kind_ = deformer;
  const Character& c = character.character();
  for (std::size_t p = 0; p < c.parts.size(); ++p) {
    const CharacterPart& part = c.parts[p];
    std::unique_ptr<PartState> st(new PartState());
    const std::size_t n = part.surface.rest_positions.size();
    st->control = part.surface.rest_positions;
    st->patches.resize(n);
    st->packed.resize(n * kPackedPatchStride);
    part.surface.domain->FitPatches(st->control.data(), st->patches.data());
    PackPatches(st->patches.data(), n, st->packed.data());
    if (const SkinRig* rig = character.rig(p)) {
      std::vector<VertexWeights> w(n);
      for (std::size_t i = 0; i < n; ++i) {
        w[i].joints = part.control_joints[i];
        w[i].weights = part.control_weights[i];
      }
      const Status s = MakeDeformer(deformer, *rig, part.surface.rest_positions.data(), nullptr,
                                    w.data(), n, &st->deformer);
      if (!s.ok()) return s.WithContext(c.asset.source + ", part " + std::to_string(p));
      st->palette.resize(rig->parents.size());
    }
    r->parts_.push_back(std::move(st));
  }
  *out = std::move(r);
  return Status::Ok();
}

void RuntimeInstance::ResetHistory() {
  for (auto& p : parts_) {
    if (p->deformer) p->deformer->ResetHistory();
  }
}

const Vec3* RuntimeInstance::control_positions(std::size_t p) const {
  return p < parts_.size() ? parts_[p]->control.data() : nullptr;
}

const float* RuntimeInstance::packed_patches(std::size_t p) const {
  return p < parts_.size() ? parts_[p]->packed.data() : nullptr;
}

std::size_t RuntimeInstance::memory_bytes() const {
  // The deformers' own tables (their copies of the weights and rest positions) are not
  // visible from here and not counted: docs/engine-integration.md says so.
  std::size_t n = sizeof(RuntimeInstance) + parts_.capacity() * sizeof(parts_[0]);
  for (const auto& p : parts_) {
    n += sizeof(PartState) + p->palette.capacity() * sizeof(glm::dmat4) +
         p->control.capacity() * sizeof(Vec3) + p->patches.capacity() * sizeof(LocalPatch) +
         p->packed.capacity() * sizeof(float);
  }
  return n;
}

bool PoseJob::Validate() const {
  if (!instance || part >= instance->parts_.size()) return false;
  const std::size_t joints = instance->character().num_joints(part);
  if (joints == 0) return num_skin_matrices == 0 && !joint_remap;
  if (!skin_matrices) return false;
  if (!joint_remap) return num_skin_matrices == joints;
  for (std::size_t j = 0; j < joints; ++j) {
    if (joint_remap[j] < 0 || static_cast<std::size_t>(joint_remap[j]) >= num_skin_matrices)
      return false;
  }
  return true;
}

bool PoseJob::Run() const {
  if (!Validate()) return false;
  RuntimeInstance::PartState& st = *instance->parts_[part];
  if (!st.deformer) return true;  // static: rest pose, patches already packed
  for (std::size_t j = 0; j < st.palette.size(); ++j) {
    const std::size_t source = joint_remap ? static_cast<std::size_t>(joint_remap[j]) : j;
    const float* m = skin_matrices + 16 * source;
    glm::dmat4& d = st.palette[j];
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) d[c][r] = static_cast<double>(m[4 * c + r]);
    }
  }
  if (!st.deformer->SetPose(st.palette.data()).ok()) return false;
  const std::size_t n = st.control.size();
  st.deformer->Deform(0, n, st.control.data(), nullptr);
  const ManifoldDomain& domain = *instance->character().character().parts[part].surface.domain;
  domain.FitPatches(st.control.data(), st.patches.data());
  PackPatches(st.patches.data(), n, st.packed.data());
  return true;
}

bool EvaluateJob::Validate() const {
  if (!output || !instance || &output->character() != &instance->character()) return false;
  const std::size_t end = std::min(block_end, output->plan().num_blocks());
  if (block_begin > end) return false;
  if (!buffers.positions || buffers.position_stride < 3 * sizeof(float)) return false;
  if (buffers.normals && buffers.normal_stride < 3 * sizeof(float)) return false;
  return SimdPathAvailable(path);
}

bool EvaluateJob::Run() const {
  if (!Validate()) return false;
  const std::size_t end = std::min(block_end, output->plan().num_blocks());
  PlanOutputBuffers b = buffers;
  if (b.tangents) {
    if (output->tangent_frames().empty()) return false;
    b.tangent_frames = output->tangent_frames().data();
  }
  return EvaluatePlan(output->plan(), instance->packed_patches(output->part()), block_begin, end, b,
                      path);
}

}  // namespace dermis

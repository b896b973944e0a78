// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The deformer table (dermis/deform/deformer.h): the one list of deformers, their names and
// their factories, read by MakeDeformer(), the C API, the character poser and the tools.
#include <string>

#include "dermis/deform/deformer.h"

namespace dermis {
namespace {

Status MakeDefaultSweepDeformer(const SkinRig& rig, const Vec3* rest_positions,
                                const Vec3* rest_normals, const VertexWeights* influences,
                                std::size_t count, std::unique_ptr<Deformer>* out) {
  return MakeSweepDeformer(rig, rest_positions, rest_normals, influences, count, SweepOptions{},
                           out);
}

constexpr DeformerInfo kDeformers[] = {
    {DeformerKind::kLbs, "lbs", "linear blend skinning", MakeLbsDeformer},
    {DeformerKind::kDqs, "dqs", "dual-quaternion skinning", MakeDqsDeformer},
    {DeformerKind::kSweep, "sweep", "the sweep-based deformer (twists unwrapped along a clip)",
     MakeDefaultSweepDeformer},
};

}  // namespace

const DeformerInfo* DeformerTable(std::size_t* count) {
  *count = sizeof(kDeformers) / sizeof(kDeformers[0]);
  return kDeformers;
}

const DeformerInfo* FindDeformer(DeformerKind kind) {
  for (const DeformerInfo& d : kDeformers) {
    if (d.kind == kind) return &d;
  }
  return nullptr;
}

const DeformerInfo* FindDeformer(std::string_view name) {
  for (const DeformerInfo& d : kDeformers) {
    if (name == d.name) return &d;
  }
  return nullptr;
}

std::vector<std::string> DeformerNames() {
  std::vector<std::string> names;
  for (const DeformerInfo& d : kDeformers) names.emplace_back(d.name);
  return names;
}

Status DeformerFromName(std::string_view name, DeformerKind* out) {
  if (const DeformerInfo* d = FindDeformer(name)) {
    *out = d->kind;
    return Status::Ok();
  }
  std::string known;
  for (const DeformerInfo& d : kDeformers)
    known += (known.empty() ? "" : ", ") + std::string(d.name);
  return Status::InvalidInput("unknown deformer '" + std::string(name) + "' (deformers: " + known +
                              ")");
}

const char* DeformerName(DeformerKind kind) {
  const DeformerInfo* d = FindDeformer(kind);
  return d != nullptr ? d->name : "unknown";
}

Status MakeDeformer(DeformerKind kind, const SkinRig& rig, const Vec3* rest_positions,
                    const Vec3* rest_normals, const VertexWeights* influences, std::size_t count,
                    std::unique_ptr<Deformer>* out) {
  const DeformerInfo* d = FindDeformer(kind);
  if (d == nullptr) {
    return Status::InvalidInput("unknown deformer " + std::to_string(static_cast<unsigned>(kind)));
  }
  return d->make(rig, rest_positions, rest_normals, influences, count, out);
}

}  // namespace dermis

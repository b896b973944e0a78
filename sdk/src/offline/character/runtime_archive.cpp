// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The runtime archive builder (offline/character/runtime_archive.h): serialise the character
// as a version-4 .dsurf (docs/file-format.md, "Runtime archives"), read it back with the
// runtime's reader, and compare the two displaced surfaces (Eq. 3-4 of docs/math.md, evaluated
// by EvaluateSamples() at the rest pose) at the level-8 tessellation and at every bound vertex.
// The error goes into the archive's header, which does not change the surface, so the bytes
// are written twice and read once.
#include "dermis/offline/character/runtime_archive.h"

#include <algorithm>
#include <cmath>

#include "dermis/core/parallel.h"
#include "dermis/surface/tessellation.h"

namespace dermis {
namespace {

constexpr int kErrorLevel = 8;

// Positions of `samples` on part `p` of `ch` at the rest pose, `threads` threads.
Status Evaluate(const Character& ch, std::size_t p, const std::vector<SampleLocation>& samples,
                int threads, std::vector<Vec3>* out) {
  const DisplacedSurface& s = ch.parts[p].surface;
  std::vector<LocalPatch> patches(s.rest_positions.size());
  s.domain->FitPatches(s.rest_positions.data(), patches.data());
  out->assign(samples.size(), Vec3(0.0));
  std::vector<char> ok(static_cast<std::size_t>(ResolveThreadCount(threads)), 1);
  const std::size_t chunks = ok.size();
  ParallelFor(threads, chunks, [&](std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c) {
      const std::size_t lo = samples.size() * c / chunks, hi = samples.size() * (c + 1) / chunks;
      ok[c] = EvaluateSamples(*s.domain, patches.data(), s.displacement.get(), samples.data() + lo,
                              hi - lo, out->data() + lo, nullptr)
                  ? 1
                  : 0;
    }
  });
  for (char c : ok) {
    if (!c)
      return Status::InvalidInput(ch.asset.source + ": part " + std::to_string(p) +
                                  ": a sample location is invalid");
  }
  return Status::Ok();
}

// Bound locations of part p in (mesh, primitive, vertex) order.
std::vector<SampleLocation> BoundLocations(const Character& ch, std::size_t p) {
  std::vector<SampleLocation> out;
  for (const auto& mesh : ch.bindings) {
    for (const auto& prim : mesh) {
      for (const VertexBinding& b : prim) {
        if (b.part == static_cast<Index>(p)) out.push_back(SampleLocation{b.face, b.u, b.v});
      }
    }
  }
  return out;
}

Status Measure(const Character& source, const Character& packed, int threads,
               RuntimeArchiveReport* report) {
  if (packed.parts.size() != source.parts.size())
    return Status::Internal("runtime archive: the part count changed");
  std::vector<std::vector<Vec3>> reference(source.parts.size()), archived(source.parts.size());
  glm::dvec3 lo(1e300), hi(-1e300);
  for (std::size_t p = 0; p < source.parts.size(); ++p) {
    TessellationPattern pattern;
    Status s = TessellationPattern::Build(source.parts[p].surface.domain->topology(), kErrorLevel,
                                          &pattern);
    if (s.ok()) s = Evaluate(source, p, pattern.samples, threads, &reference[p]);
    if (s.ok()) s = Evaluate(packed, p, pattern.samples, threads, &archived[p]);
    if (!s.ok()) return s;
    for (const Vec3& x : reference[p]) {
      lo = glm::min(lo, x);
      hi = glm::max(hi, x);
    }
  }
  RuntimeArchiveError& e = report->error;
  e = RuntimeArchiveError();
  e.diagonal = reference.empty() || lo.x > hi.x ? 0.0 : glm::length(hi - lo);
  const double scale = e.diagonal > 0.0 ? 1.0 / e.diagonal : 0.0;
  double sum = 0.0;
  report->level8_samples = 0;
  for (std::size_t p = 0; p < source.parts.size(); ++p) {
    for (std::size_t i = 0; i < reference[p].size(); ++i) {
      const double d = glm::length(archived[p][i] - reference[p][i]) * scale;
      e.level8_max = std::max(e.level8_max, d);
      sum += d;
    }
    report->level8_samples += reference[p].size();
  }
  if (report->level8_samples > 0) e.level8_mean = sum / static_cast<double>(report->level8_samples);
  report->bound_vertices = 0;
  for (std::size_t p = 0; p < source.parts.size(); ++p) {
    std::vector<Vec3> a, b;
    Status s = Evaluate(source, p, BoundLocations(source, p), threads, &a);
    if (s.ok()) s = Evaluate(packed, p, BoundLocations(packed, p), threads, &b);
    if (!s.ok()) return s;
    if (a.size() != b.size()) return Status::Internal("runtime archive: the bindings changed");
    for (std::size_t i = 0; i < a.size(); ++i)
      e.bound_max = std::max(e.bound_max, glm::length(a[i] - b[i]) * scale);
    report->bound_vertices += a.size();
  }
  return Status::Ok();
}

// What the writer relies on: surfaces, influences and bindings consistent with the asset.
Status Check(const Character& ch, const RuntimeArchiveOptions& options) {
  const std::string& name = ch.asset.source;
  if (options.keep_source && ch.source_stripped) {
    return Status::InvalidInput(name +
                                ": a runtime archive packed without its source asset; "
                                "--keep-source needs the fitted character (.dsurf) instead");
  }
  if (ch.parts.size() > 0xfffe) return Status::InvalidInput(name + ": too many parts");
  for (std::size_t p = 0; p < ch.parts.size(); ++p) {
    const CharacterPart& part = ch.parts[p];
    const std::string where = name + ": part " + std::to_string(p);
    if (!part.surface.domain || part.surface.rest_positions.size() !=
                                    static_cast<std::size_t>(part.surface.domain->num_vertices())) {
      return Status::InvalidInput(where + " has no consistent surface");
    }
    if (part.skin != kInvalidIndex &&
        (part.skin < 0 || static_cast<std::size_t>(part.skin) >= ch.asset.skins.size())) {
      return Status::InvalidInput(where + ": skin out of range");
    }
    if (part.control_joints.size() != part.control_weights.size())
      return Status::InvalidInput(where + ": control influences inconsistent");
  }
  if (ch.bindings.size() != ch.asset.meshes.size())
    return Status::InvalidInput(name + ": bindings do not match the meshes");
  for (std::size_t m = 0; m < ch.bindings.size(); ++m) {
    if (ch.bindings[m].size() != ch.asset.meshes[m].primitives.size())
      return Status::InvalidInput(name + ": bindings do not match the primitives of mesh " +
                                  std::to_string(m));
  }
  return Status::Ok();
}

}  // namespace

Status BuildRuntimeArchive(const Character& character, const RuntimeArchiveOptions& options,
                           int threads, std::string* out, RuntimeArchiveReport* report) {
  Status s = Check(character, options);
  if (!s.ok()) return s;
  RuntimeArchiveReport local;
  RuntimeArchiveReport& r = report != nullptr ? *report : local;
  const std::string first = SerializeRuntimeArchive(character, options);
  Character packed;
  DsurfFileInfo info;
  s = ParseCharacter(first, character.asset.source + " (runtime archive)", &packed, nullptr, &info);
  if (!s.ok()) return s;
  s = Measure(character, packed, threads, &r);
  if (!s.ok()) return s;
  *out = SerializeRuntimeArchive(character, options, r.error);
  r.bytes = out->size();
  r.sections = std::move(info.sections);
  return Status::Ok();
}

}  // namespace dermis

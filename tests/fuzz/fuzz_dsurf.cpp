// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// libFuzzer harness: the .dsurf reader of every version (ParseCharacter: container, surfaces,
// characters; the checksum rewritten, fuzz_checksum.h), the asset checks, then what every consumer
// does next: fit the local patches at the rest positions and evaluate one point per face
// (docs/reliability.md).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "dermis/asset/asset_validate.h"
#include "dermis/dsurf/dsurf.h"
#include "dermis/runtime/character.h"
#include "dermis/surface/surface_evaluator.h"
#include "fuzz_checksum.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes = dermis::fuzz::WithChecksum(data, size);
  dermis::Character ch;
  std::uint32_t version = 0;
  if (!dermis::ParseCharacter(bytes, "fuzz.dsurf", &ch, &version).ok()) return 0;
  if (!dermis::IsSurfaceDsurfVersion(version)) (void)dermis::ValidateAsset(ch.asset);
  for (const dermis::CharacterPart& part : ch.parts) {
    const dermis::DisplacedSurface& s = part.surface;
    if (!s.domain) continue;
    const dermis::ManifoldDomain& d = *s.domain;
    if (s.rest_positions.size() != static_cast<std::size_t>(d.num_vertices())) continue;
    std::vector<dermis::LocalPatch> patches(static_cast<std::size_t>(d.num_vertices()));
    d.FitPatches(s.rest_positions.data(), patches.data());
    for (dermis::Index f = 0; f < d.num_faces() && f < 64; ++f) {
      dermis::SurfacePoint p;
      (void)dermis::EvaluateSurface(d, patches.data(), s.displacement.get(), f,
                                    dermis::Vec2(0.25, 0.5), &p);
    }
  }
  return 0;
}

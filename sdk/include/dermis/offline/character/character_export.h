// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Turning a fitted character back into a plain asset for export: `bound` (the original
/// topology with positions and normals evaluated on the displaced surface) or `lod` (each fitted
/// part tessellated at a level, with skin weights and texture coordinates transferred).
#pragma once

#include <string>
#include <vector>

#include "dermis/asset/asset.h"
#include "dermis/core/status.h"
#include "dermis/runtime/character.h"

namespace dermis {

/// Options shared by both export modes.
struct CharacterExportOptions {
  /// Displacement levels used when evaluating (-1: all; 0: the domain surface alone).
  int displacement_levels = -1;
  /// `lod` only: segments per control-face edge (>= 1).
  int level = 4;
};

/// The character's asset with every bound vertex moved to D(z) of its fitted parameter and its
/// normal set to the surface normal there (tangents re-orthogonalised against it); vertices of
/// unfitted parts, skins, animations, materials and everything else are unchanged.
Status BuildBoundAsset(const Character& character, const CharacterExportOptions& options,
                       Asset* out);

/// The character's asset where each mesh's fitted triangles are replaced by one primitive per
/// fitted part: the tessellation at `level`, with normals from the surface, and JOINTS_0 /
/// WEIGHTS_0 and TEXCOORD_n transferred from the nearest point of the original triangles (a
/// tessellated triangle that straddles a UV seam interpolates across it: the seam is smeared
/// over one tessellation cell). A fitted mesh with morph targets is refused (kUnsupported);
/// triangles of unfitted parts, points and lines stay. `notes` (may be null) receives what
/// was dropped.
Status BuildLodAsset(const Character& character, const CharacterExportOptions& options, Asset* out,
                     std::vector<std::string>* notes);

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// What the character export builders (character_export.cpp) and the poser
// (character_pose.cpp) share: evaluating a part at rest and where each exported vertex lies on
// a part's surface. Internal header.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "dermis/asset/asset.h"
#include "dermis/core/status.h"
#include "dermis/offline/character/character_export.h"
#include "dermis/runtime/character.h"
#include "dermis/surface/bspline_displacement.h"
#include "dermis/surface/local_patch.h"

namespace dermis::character {

/// Export and posing need the source asset's vertices, skins and clips: refuse a character read
/// from a runtime archive packed without them (Character::source_stripped).
inline Status RequireSourceAsset(const Character& ch) {
  if (!ch.source_stripped) return Status::Ok();
  return Status::InvalidInput(ch.asset.source +
                              ": a runtime archive without its source asset (meshes, clips); "
                              "export, animate and render need the fitted .dsurf or an archive "
                              "packed with --keep-source");
}

/// What evaluating one part needs: its rest patches and the displacement to use.
struct PartEval {
  std::vector<LocalPatch> patches;  ///< Fitted to the rest control vertices.
  std::unique_ptr<TruncatedDisplacement> truncated;
  const Displacement* displacement = nullptr;  ///< Null: the domain surface alone.
  double orientation = 1.0;  ///< -1 if the surface normal faces against the source triangles.
};

/// The rest patches, the displacement of its first `levels` levels (-1: all, 0: none) and the
/// orientation of part `part` (the surface normal against the area-weighted normals of the
/// part's source triangles).
Status MakePartEval(const Character& ch, Index part, int levels, PartEval* e);

/// Area-weighted vertex normals of a primitive's triangles at `positions` (unit; (0, 0, 1)
/// where no triangle has area).
std::vector<Vec3> TriangleNormals(const AssetPrimitive& prim, const std::vector<Vec3>& positions);

/// Per mesh, per primitive, per vertex: where the vertex lies on a part's surface (part, face,
/// u, v), or part = kInvalidIndex. A primitive's vector is empty when none of its vertices does.
using SurfaceSources = std::vector<std::vector<std::vector<VertexBinding>>>;

/// BuildLodAsset(); if `sources` is non-null it receives, for every primitive of `out`, the
/// tessellation sample of each vertex (the part's primitives) or nothing (kept primitives).
Status BuildLodAssetWithSources(const Character& ch, const CharacterExportOptions& options,
                                Asset* out, std::vector<std::string>* notes,
                                SurfaceSources* sources);

}  // namespace dermis::character

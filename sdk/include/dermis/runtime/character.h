// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief A Dermis character: the source asset (skeleton, skins, clips, materials, meshes)
/// plus one displaced surface per fitted mesh component, skin weights on its control
/// vertices, and every original vertex bound to the surface by its fitted parameter.
/// Stored as a version-2 .dsurf file (docs/file-format.md); read and written by
/// dermis/dsurf/dsurf.h.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "dermis/asset/asset.h"
#include "dermis/core/status.h"
#include "dermis/deform/deformer.h"
#include "dermis/dsurf/dsurf.h"

namespace dermis {

/// Summary of one part's fit (paper units: the part's bounding box largest side is 1).
struct PartFitSummary {
  std::int64_t points = 0;     ///< Welded vertices of the component.
  std::int64_t triangles = 0;  ///< Triangles of the component.
  std::int64_t points_outside = 0;
  std::int64_t points_not_converged = 0;
  double scale = 1.0;                  ///< Largest side of the part's bounding box (model units).
  double e1_mean = 0.0, e1_max = 0.0;  ///< |p - D(z_p)| over the part's vertices.
  double hausdorff = 0.0;  ///< Two-sided, against the component's triangles (paper units).
  std::int64_t coefficients = 0;
  int levels = 0;
};

/// One connected component of one mesh, fitted to a displaced surface.
struct CharacterPart {
  Index mesh = kInvalidIndex;  ///< Into Asset::meshes (mesh space = bind space).
  Index component = 0;         ///< Component number within the mesh (for messages).
  Index skin = kInvalidIndex;  ///< Skin of the nodes drawing the mesh, or none (static).
  DisplacedSurface surface;    ///< Control mesh, domain, patches' operators, displacement.
  /// Influences of each control vertex (sets of 4, weights summing to 1), transferred from the
  /// dense mesh's nearest surface point. Empty for a static part.
  std::vector<glm::u16vec4> control_joints;
  std::vector<glm::vec4> control_weights;
  PartFitSummary fit;
};

/// Where an original vertex sits on the fitted surface.
struct VertexBinding {
  Index part = kInvalidIndex;  ///< Into Character::parts; none for a vertex of an unfitted part.
  Index face = kInvalidIndex;  ///< Control face of that part's surface.
  double u = 0.0, v = 0.0;     ///< Face coordinates in [0, 1]^2.
};

/// A mesh component left as an ordinary (skinned) mesh, and why.
struct UnfittedPart {
  Index mesh = kInvalidIndex;
  Index component = 0;
  std::int64_t vertices = 0, triangles = 0;
  std::string reason;
};

/// A whole character.
struct Character {
  Asset asset;
  std::vector<CharacterPart> parts;
  /// bindings[mesh][primitive][vertex]: one per vertex of every primitive of every mesh.
  std::vector<std::vector<std::vector<VertexBinding>>> bindings;
  std::vector<UnfittedPart> unfitted;
  /// True when read from a runtime archive packed without its source asset
  /// (RuntimeArchiveOptions::keep_source false): `asset` then holds only the nodes' names and
  /// parents, the skins, and each primitive's mode and indices (no vertex attributes, materials,
  /// images or clips), and the fit summaries are zero. The runtime needs nothing more; offline
  /// posing and export refuse such a character.
  bool source_stripped = false;
};

/// The rig of skin `skin` of `asset` as the deformers see it: joint j's parent is the index,
/// within the skin's joint list, of the nearest ancestor node of joint j that is itself one of
/// the skin's joints (-1 if none); its bind matrix is the inverse of its inverse bind matrix
/// (docs/notes/sweep.md section 2: not the node's rest transform, and the skinned mesh node's own
/// transform plays no part); names are the joint nodes' names.
Status MakeSkinRig(const Asset& asset, Index skin, SkinRig* out);

}  // namespace dermis

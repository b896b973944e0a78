// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Smoothing of a quad mesh on a reference surface: tangential relaxation with
/// back-projection, boundary vertices kept on their loops (docs/fitting.md, "Control mesh").
#pragma once

#include <array>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/offline/build/crease_chains.h"
#include "dermis/offline/build/reference_surface.h"
#include "dermis/offline/build/sizing_field.h"
#include "dermis/offline/geometry/polygon_mesh.h"

namespace dermis {

/// Options of RelaxQuadMesh().
struct QuadRelaxOptions {
  int iterations = 5;
  /// A move that turns a face's normal by more than this (degrees) is undone.
  double max_normal_change_deg = 60.0;
};

/// Creases of a mesh being relaxed: per vertex its feature tag (crease_chains.h) and, for a
/// vertex on a chain, its two neighbours along it. `chains` is not owned.
struct QuadRelaxFeatures {
  const CreaseChains* chains = nullptr;
  std::vector<int> feature;
  std::vector<std::array<Index, 2>> neighbors;
};

/// Relaxes the vertices of a polygon mesh (quads, or any faces) on `reference`, Jacobi style:
/// an interior vertex moves in its tangent plane to the centroid of its faces' centroids
/// weighted by area / size^2 (`sizing` at the face, so the density of the field is kept), a
/// boundary vertex moves along its loop (`loop[v]`, the reference loop of vertex v, -1 inside)
/// to the point between its two boundary neighbours; then each is projected back onto the
/// reference (the facing side; its loop for a boundary vertex). Moves that would turn a face
/// over are undone and counted in `rejected` (optional). With `features` (optional), a crease
/// vertex moves along its chain between its crease neighbours and a corner stays. The mesh must
/// be manifold.
Status RelaxQuadMesh(const ReferenceSurface& reference, const SizingField& sizing,
                     const std::vector<int>& loop, const QuadRelaxOptions& options,
                     PolygonMesh* mesh, int* rejected = nullptr,
                     const QuadRelaxFeatures* features = nullptr);

}  // namespace dermis

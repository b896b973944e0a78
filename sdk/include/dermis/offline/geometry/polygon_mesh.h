// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Checks and clean-up of polygon meshes (the type: dermis/asset/polygon_mesh.h, what the
/// scan importers fill).
#pragma once

#include <vector>

#include "dermis/asset/polygon_mesh.h"
#include "dermis/core/status.h"
#include "dermis/core/types.h"

namespace dermis {

/// Checks that the mesh can be a control mesh: at least one face; finite positions; faces of
/// >= 3 distinct, in-range vertices; manifold, consistently oriented edges and vertices; interior
/// vertices of valence >= 3. Vertices used by no face are allowed (see CompactUnusedVertices).
/// The message names the source, the element and its line where known.
Status ValidatePolygonMesh(const PolygonMesh& mesh);

/// Checks that every coordinate is finite and of magnitude at most limits::kMaxCoordinate
/// (dermis/core/limits.h), so that the products geometry forms (cross products, squared
/// distances, normals) cannot overflow. The readers keep any finite number exactly; the
/// pipelines that compute with a mesh (BuildControlSurface, ReadFitInput) call this first.
Status CheckCoordinateRange(const PolygonMesh& mesh);

/// Removes vertices that no face uses and renumbers the faces. Returns how many were removed;
/// `old_to_new` (optional) receives the new index of every old vertex or kInvalidIndex.
Index CompactUnusedVertices(PolygonMesh* mesh, std::vector<Index>* old_to_new = nullptr);

/// Axis-aligned bounding box diagonal length of the positions (0 for an empty mesh).
double BoundingBoxDiagonal(const std::vector<Vec3>& positions);

}  // namespace dermis

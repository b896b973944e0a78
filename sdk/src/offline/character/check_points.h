// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Check points of a character part: points of its source between the fitted samples, measured
// only, which decide how many displacement levels the part keeps (docs/characters.md, "Levels
// checked between the samples"). Internal header of character_fit.cpp.
#pragma once

#include <cstdint>
#include <vector>

#include "dermis/core/types.h"
#include "dermis/offline/geometry/polygon_mesh.h"
#include "dermis/offline/geometry/shading_surface.h"

namespace dermis::character {

/// Points spread over the triangles of `mesh` at random but reproducible places (a fixed hash
/// of `seed`, the face and the point's number): `per_area` points per area `spacing`^2 on
/// average, a face's expected count rounded up or down by the hash, each at a barycentric
/// position drawn uniformly over the face, on `shading` (the surface the data samples lie
/// on). Unlike a grid's, their places share no line with AreaSamples()' rows, so they see what
/// a displacement level does between those rows. Faces that are not triangles get none. At
/// most about `max_points` in all (> 0 and finite): a density that would give more is lowered
/// to that. With `normals` not null it receives each point's shading normal
/// (ShadingSurface::Normal(); zero on a face without normals), one per point.
std::vector<Vec3> CheckPoints(const PolygonMesh& mesh, const ShadingSurface& shading,
                              double spacing, double per_area, std::uint64_t seed,
                              double max_points, std::vector<Vec3>* normals = nullptr);

}  // namespace dermis::character

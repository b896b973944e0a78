// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// A character part's data samples between its vertices (docs/characters.md, "Where the
// distances are", "Smooth-shaded parts follow their shading"). Internal header of
// character_fit.cpp.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "dermis/core/types.h"
#include "dermis/offline/geometry/polygon_mesh.h"
#include "dermis/offline/geometry/shading_surface.h"

namespace dermis::character {

/// Extra data points on the triangles, so the surface follows the source between its
/// vertices: inside every triangle longer than twice `spacing`, a barycentric grid of about
/// `spacing`, or on a sliver (less than a quarter as high as long) rows parallel to its longest
/// edge at most `spacing` apart, each with points at most `spacing` apart (a grid would pack its
/// points across the sliver as many times closer as it is narrower); and points about
/// `spacing` apart along every edge longer than that (the vertices are data already). Edges where
/// the source turns sharply (boundaries, and creases whose dihedral angle exceeds `crease_angle`
/// radians) get them `crease_factor` times closer (or as close as their faces' spacing below,
/// where that is closer): the smooth domain surface rounds a crease, and only
/// data on the crease line ask the displacement to follow it (docs/characters.md, "Where the
/// distances are"). With `crease_rows`, rows of points beside those edges fill the gap to the
/// samples inside a triangle longer than twice `spacing`, a sliver's included (area_samples.cpp).
///
/// An edge in `smooth_edges` (sorted (a, b), a < b) is never sharp: the source shades it smooth.
///
/// The points lie on `shading` (the flat triangles where its shape factor is 0): the surface
/// the source's shading normals describe, which keeps hard edges straight.
///
/// With `turn_per_sample` > 0 (radians), a sliver where the part curves is sampled closer: two
/// faces that meet at an edge that is not sharp turn the normal by the angle between them across
/// their mean height over it, and a sliver's rows, its points on them and the points on its
/// edges come at most turn_per_sample of that turn apart (where that is closer than
/// `spacing`; a neighbour wound the other way counts with its normal flipped). A character's
/// low-poly part asks for it: its remesh's control edges are as short along a curved sliver
/// (docs/characters.md, "Samples as close as the control edges along curved slivers"). 0:
/// `spacing` everywhere.
std::vector<Vec3> AreaSamples(const PolygonMesh& mesh, const ShadingSurface& shading,
                              const std::vector<std::array<std::uint32_t, 2>>& smooth_edges,
                              double spacing, double crease_angle, double crease_factor,
                              bool crease_rows, double turn_per_sample = 0.0);

}  // namespace dermis::character

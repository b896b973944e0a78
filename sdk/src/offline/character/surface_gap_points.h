// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Points of a character part's source where its fitted surface leaves it (docs/characters.md,
// "Where the surface leaves the source"). Internal header of character_fit.cpp.
#pragma once

#include <vector>

#include "dermis/core/types.h"
#include "dermis/offline/fit/surface_fit.h"
#include "dermis/offline/geometry/shading_surface.h"
#include "dermis/offline/geometry/triangle_distance.h"

namespace dermis::character {

/// The fit places the surface at its data points' parameters, so a bulge of the surface that no
/// data point projects onto (beyond a pointed corner of the source) is seen by none of the
/// fit's errors at its points; only the surface -> source half of the two-sided distance sees
/// it. This evaluates the fitted, displaced surface at `per_edge` x `per_edge` points of every
/// control face (the centres of a per_edge x per_edge split of its parameter square) and, for
/// each farther than `max_distance` (model units) from the source, returns the source's point
/// nearest it: the closest point on `tree`'s triangles (the source's, in the order `shading` was
/// built on) moved onto `shading` at the same barycentric weights. In face order, then row by
/// row: the same points whatever the thread count. None where max_distance is not positive or
/// per_edge < 1.
std::vector<Vec3> SurfaceGapPoints(const FittedSurface& fitted, const TriangleDistanceTree& tree,
                                   const ShadingSurface& shading, double max_distance,
                                   int per_edge);

}  // namespace dermis::character

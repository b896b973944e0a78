// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Parameters for the points the per-point optimisation could not place: the closest
/// point of the fitted surface (docs/fitting.md, "Points the optimisation loses").
#pragma once

#include <cstdint>
#include <vector>

#include "dermis/core/types.h"
#include "dermis/offline/fit/point_fit.h"

namespace dermis {

class Displacement;
class ManifoldDomain;
struct LocalPatch;

/// For every fit with status kNotConverged: the parameter of its point's closest point on the
/// displaced surface D (paper Eq. 4, `displacement` may be null for the domain surface).
/// Gauss-Newton (ClosestPointOnSurface) runs from two starts, the fit's own parameter and the
/// nearest sample of a grid of `level` (at least 1) segments per edge over the faces within two
/// face rings of the parameter's face (so a start in a wrong basin, which the projection gave
/// it, does not decide); where the closer result lies within 0.05 (face coordinates) of a
/// boundary edge, a one-dimensional search along every boundary edge of those faces follows
/// (Gauss-Newton halves a step that leaves the surface, and so stops short of a closest point on
/// the boundary). The best point replaces the fit's face and uv where it is closer than the
/// fit's own parameter. Status, delta and the chart samples are left as they were (the point
/// still did not converge; the displacement fit never used it). Fits whose face is invalid, and
/// points that are not finite, are left alone. Per point, independent of the thread count
/// (`threads` 0: all cores). Returns how many parameters were replaced; 0 (nothing changed)
/// if `fits` and `points` differ in size.
std::int64_t PlaceLostPoints(const ManifoldDomain& domain, const LocalPatch* patches,
                             const Displacement* displacement, const std::vector<Vec3>& points,
                             std::vector<PointFit>* fits, int level = 8, int threads = 0);

}  // namespace dermis

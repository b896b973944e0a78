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
/// displaced surface D (paper Eq. 4, `displacement` may be null for the domain surface), by
/// Gauss-Newton (ClosestPointOnSurface) from two starts, the fit's own parameter and the
/// nearest sample of a grid of `level` segments per edge over the faces within two face rings
/// of the parameter's face (so a start in a wrong basin, which the projection gave it, does
/// not decide); the closer result replaces
/// the fit's face and uv where it is closer than the fit's own parameter. Status, delta and the
/// chart samples are left as they were (the point still did not converge; the displacement
/// fit never used it). Per point, independent of the thread count (`threads` 0: all cores).
/// `fits` and `points` have the same size. Returns how many parameters were replaced.
std::int64_t PlaceLostPoints(const ManifoldDomain& domain, const LocalPatch* patches,
                             const Displacement* displacement, const std::vector<Vec3>& points,
                             std::vector<PointFit>* fits, int level = 8, int threads = 0);

}  // namespace dermis

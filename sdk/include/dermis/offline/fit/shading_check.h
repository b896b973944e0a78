// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The check points' shading rule (docs/characters.md, "Levels checked by the shading"):
/// a displacement level that turns the surface's normals away from the source's shading
/// normals at the check points is dropped, with the levels after it.
#pragma once

#include <vector>

#include "dermis/core/types.h"
#include "dermis/offline/fit/point_fit.h"
#include "dermis/surface/bspline_displacement.h"
#include "dermis/surface/local_patch.h"
#include "dermis/surface/manifold_domain.h"

namespace dermis {

/// The mean angle (radians) between the displaced surface's normal and the shading normal at
/// the check points, with the first L levels of `displacement` for L = 0 .. max_levels()
/// (max_levels() + 1 entries). Check point i is evaluated at its fitted parameter `fits[i]`
/// (FitPoints(); only points with status kOptimized count, those the distance rule measures)
/// and compared with `normals[i]` (normalised; a zero vector leaves the point out) as lines, so a
/// source whose normals point against the surface's orientation is measured as one whose normals do
/// not. `patches`: one per domain vertex. Entries are 0 where no point counts. Deterministic
/// whatever `threads` (a fixed order of summation).
std::vector<double> CheckPointNormalAngles(const ManifoldDomain& domain, const LocalPatch* patches,
                                           const BsplineDisplacement& displacement,
                                           const std::vector<PointFit>& fits,
                                           const std::vector<Vec3>& normals, int threads);

/// How many levels the shading rule keeps, given CheckPointNormalAngles()' angles: the
/// trailing levels are dropped while the last one left leaves the mean angle larger than the
/// levels before it did, by more than `tolerance` (relative, >= 0). Returns
/// angles.size() - 1 when none is dropped (0 for an empty vector).
int ShadingCheckLevels(const std::vector<double>& angles, double tolerance);

/// `data` (additive form) with every chart cut to its first `levels` levels (>= 0), and the
/// trailing levels of a chart it cuts that have no coefficient left out, as a fit with that
/// many levels stores it. Returns `data` unchanged for the merged form or when no chart has
/// more levels.
BsplineDisplacementData TruncateBsplineLevels(const BsplineDisplacementData& data, int levels);

}  // namespace dermis

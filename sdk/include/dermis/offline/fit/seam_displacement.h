// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Displacements that vanish along a cut crease (docs/characters.md, "Hard edges cut
/// open"): the two sides of a cut meet exactly in their domain surfaces (the seam patch
/// operators), but a displacement moves each side along its own normal, so the displaced
/// surface stays closed only where every chart on the cut has no displacement along its
/// boundary rays.
#pragma once

#include <cstdint>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/surface/bspline_displacement.h"
#include "dermis/surface/manifold_domain.h"

namespace dermis {

/// For every chart v with seam[v] != 0 (CutAlongCreases' seam), changes each level of its
/// B-spline (additive form) by the least sum of squared coefficient changes that makes it
/// vanish on the chart's boundary rays: the whole x-axis of a half-disk chart (kCrease), the
/// rays x >= 0 and y >= 0 of a convex corner, x >= 0 and y <= 0 of a concave one. On a
/// uniform cubic lattice the level restricted to a line of the lattice is a spline whose
/// coefficients are the weighted sums of the 3 or 4 node rows its basis reaches there, so
/// each ray is one linear condition per node column (row) it crosses; a corner's two sets
/// share the nodes round the origin and are met by alternating projections. Nodes a sparse
/// level lacks are added where the change makes them non-zero; `nodes_added` (optional)
/// counts them. The coefficients are stored as float, so the displacement on a ray is zero to
/// float rounding. InvalidInput for data that is not additive, invalid
/// (ValidateBsplineDisplacementData) or not of the domain's chart count, or seam marks of
/// another count.
Status ZeroDisplacementOnSeams(const ManifoldDomain& domain, const std::vector<std::uint8_t>& seam,
                               BsplineDisplacementData* data, std::int64_t* nodes_added = nullptr);

}  // namespace dermis

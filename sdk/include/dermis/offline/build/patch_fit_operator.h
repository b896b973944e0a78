// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The linear operator of Yoon's local-patch fit (paper Eq. 2) for one chart type.
///
/// Minimise sum_k |v_k - P(z_k)|^2 subject to P(0) = v over the 8 free bi-quadratic
/// coefficients, with z_k the chart images of the 2K (2K + 1 on a boundary) one-ring control
/// vertices. Where the least-squares problem is rank deficient (valence 3: 6 equations; boundary
/// rings) the solution is made unique by the smallest thin-plate energy
/// int (P_xx^2 + 2 P_xy^2 + P_yy^2) over the chart's disk (or sector) among all least-squares
/// minimisers. Full-rank problems are plain least squares, so valence 4 interpolates its 8
/// neighbours exactly. See docs/math.md.
#pragma once

#include <vector>

#include "dermis/core/status.h"
#include "dermis/surface/chart.h"

namespace dermis {

/// Chart positions of the patch ring, in ManifoldDomain::patch_ring() order: per ring face f the
/// edge neighbour phi(f, 1) and the diagonal neighbour phi(f, 1 + i); on a boundary also
/// phi(K - 1, i).
std::vector<Vec2> PatchRingChartPositions(const ChartParams& chart);

/// Computes the row-major 8 x n operator (n = ring size) for `chart`. `rank` (optional)
/// receives the numerical rank of the least-squares system.
Status ComputePatchFitOperator(const ChartParams& chart, std::vector<double>* op,
                               int* rank = nullptr);

}  // namespace dermis

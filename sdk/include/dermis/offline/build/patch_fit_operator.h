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

#include <cstdint>
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

/// How the patch of a boundary vertex on a cut crease meets the patches across the cut
/// (docs/characters.md, "Hard edges cut open"). A cut crease leaves two boundaries over the
/// same control vertices, one per side; the surface along a boundary edge is the blend of its
/// two end vertices' patches restricted to the edge (the partition of unity and the chart maps
/// along a boundary edge depend on the edge alone: p = 1 on boundary charts), so the two sides
/// meet exactly where each patch's restriction to its boundary rays depends only on the
/// vertices of the crease.
enum class SeamMode : std::uint8_t {
  kNone = 0,    ///< An ordinary vertex: ComputePatchFitOperator().
  kSmooth = 1,  ///< Inside a crease chain: along both boundary rays the parabola through the two
                ///< boundary neighbours and the vertex (parameter +1 and -1 at the neighbours).
  kCorner = 2,  ///< A chain's corner or end: a straight line to each boundary neighbour (the
                ///< chart must be a corner chart, its rays on different axes).
};

/// The operator of a boundary chart whose patch follows `mode` along its boundary rays (the
/// ring's first and last entries, the two boundary neighbours, are interpolated) and fits the
/// other ring positions by least squares over the coefficients left, with the smallest
/// thin-plate energy where they do not fix them. kNone gives ComputePatchFitOperator();
/// InvalidInput for an interior chart, or kCorner on a chart whose two rays lie on one axis.
Status ComputeSeamPatchFitOperator(const ChartParams& chart, SeamMode mode, std::vector<double>* op,
                                   int* rank = nullptr);

}  // namespace dermis

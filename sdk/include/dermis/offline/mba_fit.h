// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Multilevel B-spline approximation (MBA) of scattered values on one chart
/// (Lee, Wolberg and Shin 1997; fitting.md section 1).
#pragma once

#include <cstddef>
#include <vector>

#include "dermis/core/types.h"

namespace dermis {

/// Fits f on the square [-half_extent, half_extent]^2 to the values at points z (chart
/// coordinates) with `num_levels` levels of BA (level k: 2^k cells per side). Level k's fit
/// approximates the residual left by levels 0..k-1; the merged lattices Psi_0 .. Psi_{h-1}
/// (layout of BsplineDisplacementData::values) are appended to *lattices, so truncating
/// at L levels gives exactly the function of an L-level fit. Points outside the square are
/// clamped onto it. If `residuals` is not null it receives value - f(z) per point.
/// `finest_passes` (>= 1) runs the finest level's BA that many times, each pass on the residual
/// the previous ones left, adding to the same lattice: BA is only an approximate projection
/// where points share control nodes, and the repeated passes converge towards the fit at that
/// lattice spacing instead of going to a finer, rippling level. Coarser lattices are unaffected.
/// Deterministic: the points are accumulated in the order given.
void FitMultilevelBspline(const Vec2* z, const double* values, std::size_t count,
                          double half_extent, int num_levels, std::vector<double>* lattices,
                          std::vector<double>* residuals = nullptr, int finest_passes = 1);

/// Cubic B-spline midpoint refinement (fitting.md section 1): the level-(k+1) lattice, (2m+3)^2,
/// of the function of a level-k lattice with m cells per side. Exact on [0, m]^2.
void RefineBsplineLattice(const double* coarse, int m, double* fine);

}  // namespace dermis

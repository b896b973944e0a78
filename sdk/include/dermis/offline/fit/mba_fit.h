// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Multilevel B-spline approximation (MBA) of scattered values on one chart
/// (Lee, Wolberg and Shin 1997; docs/notes/fit.md section 1).
#pragma once

#include <cstddef>
#include <vector>

#include "dermis/core/types.h"

namespace dermis {

/// How the finest level of FitMultilevelBspline() is fitted.
struct MbaOptions {
  /// BA passes at the finest level (>= 1), each on the residual the previous ones left, adding
  /// to the same lattice: BA is only an approximate projection where points share control
  /// nodes, and repeated passes converge towards the fit at that lattice spacing.
  int finest_passes = 1;
  /// > 0: after the passes, the finest level's whole correction (the sum of its passes) is
  /// re-solved as the smoothing spline (SmoothBsplineFit(), dermis/offline/fit/bspline_smoothing.h)
  /// of the residual that entered the level, with this weight, started from that sum. 0: plain
  /// MBA.
  double smoothing = 0.0;
  double tension = 10.0;  ///< Membrane weight in the data's gaps (SmoothBsplineFit()), >= 0.
  int smoothing_iterations = 40;  ///< Conjugate-gradient steps at most.
};

/// Fits f on the square [-half_extent, half_extent]^2 to the values at points z (chart
/// coordinates) with `num_levels` levels of BA (level k: 2^k cells per side). Level k's fit
/// approximates the residual left by levels 0..k-1; the merged lattices Psi_0 .. Psi_{h-1}
/// (layout of BsplineDisplacementData::values) are appended to *lattices, so truncating
/// at L levels gives exactly the function of an L-level fit with the default MbaOptions (the
/// options change only the finest level). Points outside the square are clamped onto it. If
/// `residuals` is not null it receives value - f(z) per point. Deterministic: the points are
/// accumulated in the order given.
void FitMultilevelBspline(const Vec2* z, const double* values, std::size_t count,
                          double half_extent, int num_levels, std::vector<double>* lattices,
                          std::vector<double>* residuals = nullptr,
                          const MbaOptions& options = MbaOptions{});

/// Cubic B-spline midpoint refinement (docs/notes/fit.md section 1): the level-(k+1) lattice,
/// (2m+3)^2, of the function of a level-k lattice with m cells per side. Exact on [0, m]^2.
void RefineBsplineLattice(const double* coarse, int m, double* fine);

}  // namespace dermis

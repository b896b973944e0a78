// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Fits the multilevel B-spline displacement of every chart to displacement samples
/// (paper section 4, "Optimal displacement function"; docs/notes/fit.md sections 1 and 6).
#pragma once

#include <vector>

#include "dermis/offline/fit/point_fit.h"
#include "dermis/surface/bspline_displacement.h"
#include "dermis/surface/manifold_domain.h"

namespace dermis {

/// Options of FitDisplacements().
struct DisplacementFitOptions {
  /// Upper bound on the levels of any chart (1 .. kMaxBsplineLevels).
  int max_levels = 8;
  /// Levels per chart: the finest lattice has about `density` * sqrt(samples) cells per side
  /// (docs/notes/fit.md section 6), so the lattice spacing follows the local point spacing. 0 gives
  /// every chart `max_levels`.
  double density = 1.0;
  /// BA passes at each chart's finest level (MbaOptions::finest_passes), >= 1.
  int finest_passes = 1;
  /// Thin-plate weight of the finest level's smoothing spline (MbaOptions::smoothing); 0:
  /// plain MBA. See docs/fitting.md for how 5e-4 was chosen.
  double smoothing = 5e-4;
  int threads = 0;  ///< 0: hardware concurrency.
};

/// Half side of chart v's square domain: it holds the image of every point where the chart's
/// weight is positive (|w| < sqrt(2) ub in each ring face, so |z| < (sqrt(2) ub)^p), padded by
/// 2%. Depends only on the chart, never on the data (docs/notes/fit.md section 1).
double ChartHalfExtent(const ChartParams& chart, double blend_lb);

/// The number of levels chosen for a chart with `samples` samples.
int ChooseLevels(std::size_t samples, const DisplacementFitOptions& options);

/// Groups the samples by chart (keeping their order) and fits each chart by MBA, in parallel
/// over charts. Charts without samples get 0 levels (d = 0). Deterministic.
BsplineDisplacementData FitDisplacements(const ManifoldDomain& domain,
                                         const std::vector<ChartSample>& samples,
                                         const DisplacementFitOptions& options);

}  // namespace dermis

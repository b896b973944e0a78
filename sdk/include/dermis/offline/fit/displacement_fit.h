// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Fits the multilevel B-spline displacement of every chart to displacement samples
/// (paper section 4, "Optimal displacement function"; docs/notes/fit.md sections 1 and 6).
#pragma once

#include <vector>

#include "dermis/offline/fit/adaptive_displacement_fit.h"
#include "dermis/offline/fit/point_fit.h"
#include "dermis/surface/bspline_displacement.h"
#include "dermis/surface/local_patch.h"
#include "dermis/surface/manifold_domain.h"

namespace dermis {

/// How the displacement functions are fitted.
enum class DisplacementMethod {
  /// FitAdaptiveDisplacement(): levels refined where the data support them, fitted jointly
  /// over the charts, as many levels as a validation split finds useful (the default).
  kAdaptive,
  /// FitDisplacements(): per-chart multilevel B-spline approximation with dense lattices, the
  /// level count set by `density` (the paper's method; .dsurf version 1 storage).
  kMba,
};

/// Options of FitDisplacements() and of the displacement stage of FitSurface().
struct DisplacementFitOptions {
  DisplacementMethod method = DisplacementMethod::kAdaptive;
  /// Upper bound on the levels of any chart (1 .. kMaxBsplineLevels).
  int max_levels = 10;
  /// kAdaptive: the criteria, smoothing and stopping rule (its max_levels and threads are
  /// replaced by the ones here).
  AdaptiveDisplacementOptions adaptive;
  // kMba only:
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

/// The displacement targets of the optimised points among `fits` (status kOptimized; the
/// others are left out, as their per-chart samples contradict each other), in order: the
/// weight psi_j and unit patch normal N_j of every chart with a positive weight at the point's
/// fitted parameter, and its common displacement. `index`, if not null, receives the position
/// in `fits` of each target.
void MakeDisplacementTargets(const ManifoldDomain& domain, const LocalPatch* patches,
                             const std::vector<PointFit>& fits,
                             std::vector<DisplacementTarget>* targets,
                             std::vector<std::size_t>* index = nullptr);

/// Groups the samples by chart (keeping their order) and fits each chart by MBA, in parallel
/// over charts. Charts without samples get 0 levels (d = 0). Deterministic.
BsplineDisplacementData FitDisplacements(const ManifoldDomain& domain,
                                         const std::vector<ChartSample>& samples,
                                         const DisplacementFitOptions& options);

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Per-point projection and optimisation of a point cloud against a control surface
/// (paper section 4: "Initial displacements" and "Optimal displacement function").
#pragma once

#include <cstdint>
#include <vector>

#include "dermis/core/types.h"
#include "dermis/offline/build/domain_builder.h"

namespace dermis {

/// One scalar displacement sample of one chart.
struct ChartSample {
  Index chart = kInvalidIndex;  ///< The chart's vertex.
  Vec2 z{0.0};                  ///< Chart coordinates.
  double value = 0.0;           ///< Displacement (model units).
};

/// What happened to one data point.
enum class PointFitStatus : std::uint8_t {
  kOptimized = 0,     ///< Q(z) + delta N~(z) = p solved; all charts get the same delta.
  kNotConverged = 1,  ///< The solve failed (the detail folds over N~ here): only the
                      ///< projection's per-chart samples exist; the optimised fit leaves the
                      ///< point out, and E1 measures it at its projection parameter.
  kOutside = 2,       ///< Left every chart during projection: not used.
};

/// The parameters and samples of one data point.
struct PointFit {
  PointFitStatus status = PointFitStatus::kOutside;
  /// Surface parameter of the point: the optimised one, or the projection's if not converged
  /// (FitSurface then replaces a lost point's with its closest surface point's,
  /// PlaceLostPoints()).
  Index face = kInvalidIndex;
  Vec2 uv{0.0};
  /// The Yoon projection's parameter (on the nearest corner's patch), for the unoptimised fit;
  /// for a point FitPoints() started again (below), the closest surface point's.
  Index projected_face = kInvalidIndex;
  Vec2 projected_uv{0.0};
  double delta = 0.0;  ///< Common displacement (kOptimized) or the first chart's projection one.
  int num_optimized = 0;
  ChartSample optimized[4];  ///< The same delta on every chart with weight > 0 at the point.
  int num_projected = 0;
  ChartSample projected[4];  ///< Yoon's per-chart projections and signed distances.
};

/// Options of FitPoints().
struct PointFitOptions {
  int threads = 0;           ///< 0: hardware concurrency.
  bool optimize = true;      ///< false: projection only (the paper's "without optimization").
  double tolerance = 1e-10;  ///< Residual of the common-displacement solve, model units.
  /// false: the parameter, status and delta only; the per-chart projections of the face's other
  /// corners (`PointFit::projected`, a few Newton steps each) are skipped. The parameters are the
  /// same either way; the control-vertex fit's rounds need nothing else.
  bool chart_samples = true;
  /// With `optimize` false: still solve for the common displacement where the projection's
  /// face has a boundary vertex (the control-vertex fit measures the point distance there,
  /// which needs the exact foot point; elsewhere the projection's parameter is enough for it),
  /// and where no corner's projection stays in its chart (then there is no parameter without
  /// the solve).
  bool optimize_beside_boundary = false;
};

/// Projects every point (paper section 4): closest control face, its nearest corner, Newton on
/// that corner's patch, transitions to the other corners of the face and a few Newton steps on
/// each; then solves Q(z) + delta N~(z) = p (docs/notes/fit.md section 4b) from the projection.
/// An optimised fit whose |delta| (the solve's own measure; N~ is not unit length) exceeds the
/// distance to the closest control face by more than a twentieth of that face's longest edge
/// is a root on a distant part of the surface: the point starts again from its closest point
/// on the domain surface (searched from the control face's parameter and its centre) and
/// keeps the fit with the smaller |delta| (docs/fitting.md, "Points fitted to a distant
/// root"). Points the solve loses are not started again (PlaceLostPoints places them later).
/// Results are per point, independent of the thread count.
void FitPoints(const ControlSurface& surface, const std::vector<Vec3>& points,
               const PointFitOptions& options, std::vector<PointFit>* out);

}  // namespace dermis

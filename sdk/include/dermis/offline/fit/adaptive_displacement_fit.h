// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Adaptive multilevel displacement fitting: coarse-to-fine B-spline levels whose nodes
/// are activated only where the data support them (data density and residual), fitted jointly
/// over every chart as penalised least squares of the displaced surface's error at the fitted
/// parameters, with a fixed-seed validation split deciding how many levels to keep
/// (docs/fitting.md, "Adaptive displacement levels").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/core/types.h"
#include "dermis/offline/fit/displacement_level_fit.h"
#include "dermis/surface/bspline_displacement.h"

namespace dermis {

/// Options of FitAdaptiveDisplacement().
struct AdaptiveDisplacementOptions {
  /// Most levels of any chart (1 .. kMaxBsplineLevels).
  int max_levels = 10;
  /// Density criterion: a node of a chart's lattice is a candidate only if the points under its
  /// support weigh at least this much, sum over them of psi_j(p) B_node(z_j(p)) (the weights
  /// of all nodes and charts at a point sum to 1, so no level can hold more nodes than
  /// points / min_node_weight).
  double min_node_weight = 0.15;
  /// Residual criterion: a candidate node of level k > 0 is activated only if the weighted RMS
  /// residual of its points (after levels 0..k-1) exceeds residual_threshold times the mean
  /// validation error of level k - 1. 0 turns the criterion off.
  double residual_threshold = 0.5;
  /// Coefficient budget: at most this many coefficients per fitted point over all levels; a
  /// level that would exceed it keeps the nodes with the largest residual (and is the last
  /// one). 0: no budget.
  double max_coefficients_per_point = 3.0;
  /// An absolute coefficient budget instead (for example per source vertex of a character
  /// whose fitted points include extra samples); < 0: use max_coefficients_per_point.
  std::int64_t max_coefficients = -1;
  /// Thin-plate weight per level, relative to the mean data weight of a chart's active nodes.
  double smoothing = 1e-3;
  /// Fraction of the points set aside to choose the number of levels (stopping rule), in
  /// [0, 1); 0 fits max_levels levels (or until no node is supported).
  double validation = 0.1;
  std::uint64_t validation_seed = 0x76616c69u;
  /// The stopping rule: level k is kept only if it lowers the mean validation error by at
  /// least this fraction.
  double min_improvement = 0.01;
  /// The check points' rule (targets with DisplacementTarget::check: points between the
  /// fitted ones, never fitted): the final fit drops the levels after the last one that lowered
  /// the check points' mean error by at least this fraction, provided the levels it keeps bring
  /// them closer than no level does by that fraction (where none does, their mean cannot tell
  /// what the levels are for, and every level stays). A level that follows the fitted points
  /// and adds nothing between them fails it where a validation split, on the same lines as the
  /// fitted points, does not; a level that makes them worse before finer ones bring them
  /// closer is kept (docs/characters.md, "Levels checked between the samples"). In [0, 1);
  /// ignored without check points.
  double check_improvement = 0.01;
  /// The check points' shading rule (FitSurface(), with FitInput::check_normals): after the
  /// rule above, the trailing levels are dropped while the last one left turns the surface's
  /// normals away from the shading normals at the check points, their mean angle larger than
  /// the levels before it left it by more than this fraction (docs/characters.md, "Levels
  /// checked by the shading"). >= 0; ignored without check normals. At 0 a trailing level
  /// must not turn them away at all: CesiumMan's third level, 0.44 % worse, still left
  /// visible ridges at the hips.
  double check_shading_tolerance = 0.0;
  /// Conjugate-gradient steps per level, at most.
  int solver_iterations = 12;
  /// ... or once the residual norm is below this fraction of the right-hand side's.
  double solver_tolerance = 1e-6;
  /// Weight of the charts' agreement with the common displacement (LevelFitOptions).
  double consistency = 0.1;
  int threads = 0;  ///< 0: hardware concurrency. The result does not depend on it.
};

/// One level of the stopping rule's trial fit.
struct AdaptiveLevelReport {
  int level = 0;
  std::int64_t nodes = 0;        ///< Active nodes over all charts.
  double train_mean = 0.0;       ///< Mean |D - p| of the trial fit's points (model units).
  double validation_mean = 0.0;  ///< Mean |D - p| of the validation points.
  int iterations = 0;            ///< Solver steps taken.
};

/// What FitAdaptiveDisplacement() did.
struct AdaptiveDisplacementReport {
  std::vector<AdaptiveLevelReport> trial;  ///< The stopping rule's trial levels, in order.
  int levels = 0;                          ///< Levels kept.
  /// What ended the levels: "validation" (the stopping rule), "fitted points" (without a
  /// validation split: the fitted points' error), "check points" (their rule), "check normals"
  /// (the shading rule, FitSurface()), "budget" (the coefficient budget was spent), "no
  /// supported node" (the density and residual criteria left none) or "max levels".
  std::string stopped_by;
  std::int64_t coefficients = 0;          ///< Stored coefficients of the final fit.
  std::vector<std::int64_t> level_nodes;  ///< Active nodes per kept level (final fit).
  /// With check points: their count, and (where their distances decide) their mean |D - p|
  /// (model units) with no level and after each level the final fit added before the check
  /// points' rule, which keeps the first `levels` (or, after the shading rule, `levels` +
  /// shading_levels_dropped of them).
  std::int64_t check_points = 0;
  std::vector<double> check_mean;
  /// With check normals (FitSurface()): the mean angle (degrees) between the surface's normal
  /// and the shading normal at the check points with no level and with each of the levels the
  /// rule above kept, and how many of those the shading rule then dropped (`levels` counts
  /// the levels left).
  std::vector<double> check_angle_deg;
  int shading_levels_dropped = 0;
};

/// Whether target i belongs to the validation split (a fixed hash of i and the seed).
bool IsValidationPoint(std::size_t i, double fraction, std::uint64_t seed);

/// Fits the additive multilevel displacement of every chart (BsplineLevelForm::kAdditive) to
/// `targets`, charts of half extents `half_extent` (ChartHalfExtent()). Level by level, coarse
/// to fine: the candidate nodes are those the density criterion admits, the residual
/// criterion keeps those where the fit is still poor, and the level's correction minimises
///   sum_p |D(z_p) - p|^2 + sum_charts lambda_c (thin-plate energy + 1e-6 |phi|^2)
/// over the active nodes of every chart jointly (conjugate gradients, deterministic). A first
/// pass on the points outside the validation split picks the number of levels (the stopping
/// rule); the result is then fitted on every point with that many levels. Targets marked
/// `check` are never fitted: they only decide how many of those levels stay
/// (check_improvement). Deterministic whatever the thread count.
Status FitAdaptiveDisplacement(const std::vector<double>& half_extent,
                               const std::vector<DisplacementTarget>& targets,
                               const AdaptiveDisplacementOptions& options,
                               BsplineDisplacementData* out, AdaptiveDisplacementReport* report);

}  // namespace dermis

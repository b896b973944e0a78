// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief One level of the adaptive displacement fit: which lattice nodes of every chart the
/// data support (density and residual criteria), and the level's correction as penalised least
/// squares over every chart jointly (docs/fitting.md, "Adaptive displacement levels").
#pragma once

#include <cstdint>
#include <vector>

#include "dermis/core/types.h"

namespace dermis {

/// One fitted point as the displacement fit sees it. At the point's fitted parameter the
/// surface is D = Q + sum_j psi_j d_j(z_j) N_j (paper Eq. 3-4) and the point is
/// p = Q + delta sum_j psi_j N_j (docs/notes/fit.md section 4b), so D - p = sum_j a_j (d_j(z_j) -
/// delta) with a_j = psi_j N_j: linear in the displacement coefficients.
struct DisplacementTarget {
  int count = 0;                  ///< Charts with a positive weight at the point (1..4).
  Index chart[4] = {0, 0, 0, 0};  ///< Their vertices.
  Vec2 z[4];                      ///< The point in each chart's coordinates.
  Vec3 a[4];                      ///< psi_j N_j: weight times unit patch normal.
  double delta = 0.0;             ///< The common displacement (model units).
  /// Weight of the point's squared error in the least squares (> 0): a character's vertices
  /// weigh more than the samples between them (FitInput::weights).
  double weight = 1.0;
  /// A check point: measured only, never fitted (FitAdaptiveDisplacement() drops the levels
  /// after the last one that brought the check points closer; FitInput::check_points).
  bool check = false;
};

/// Options of DisplacementLevelFitter.
struct LevelFitOptions {
  /// Density criterion: a node is a candidate only if the points under its support weigh at
  /// least this much: sum over the points of psi_j(p) B_node(z_j(p)). The weights of every
  /// node of every chart at a point sum to 1, so a level never holds more than
  /// points / min_node_weight nodes.
  double min_node_weight = 0.15;
  /// Thin-plate weight of a chart's level, relative to the mean data weight of its nodes.
  double smoothing = 1e-3;
  int iterations = 12;  ///< Conjugate-gradient steps per level, at most.
  /// The solver stops once the residual norm falls below this fraction of the right-hand side's.
  double tolerance = 1e-6;
  /// Weight of the consistency term: every chart's agreement with the common displacement,
  /// sum over samples psi_j (d_j(z_j) - delta)^2, next to the surface error.
  double consistency = 0.1;
  int threads = 1;
};

/// Fits additive cubic B-spline levels (level k: 2^k cells per side on chart c's square
/// [-half_extent[c], half_extent[c]]^2) to targets coarse to fine, one level per FitLevel()
/// call, each on the errors the previous ones left. Only the targets in `fit` are fitted; those
/// in `eval` are only measured (a validation split). Deterministic whatever the thread count.
class DisplacementLevelFitter {
 public:
  /// `targets` and `half_extent` must outlive the fitter. Charts of the targets must be valid
  /// indices into half_extent (not checked here).
  DisplacementLevelFitter(const std::vector<double>& half_extent,
                          const std::vector<DisplacementTarget>& targets,
                          std::vector<std::uint32_t> fit, std::vector<std::uint32_t> eval,
                          const LevelFitOptions& options);

  /// Fits level `level` (>= 0, levels in increasing order). A node is active if it passes the
  /// density criterion and, when residual_threshold > 0, the residual criterion: the
  /// weighted RMS error of its points, sqrt(sum psi B |D - p|^2 / sum psi B), exceeds
  /// residual_threshold (model units). If more than max_nodes (>= 0; < 0: no limit) nodes
  /// qualify, the max_nodes with the largest weighted squared error sum psi B |D - p|^2 are
  /// kept (a coefficient budget). The correction on the active nodes minimises
  ///   sum_p |D(z_p) - p|^2 + sum_c lambda_c (E_c + 1e-6 |phi_c|^2)
  /// (E_c the discrete thin-plate energy of chart c's lattice, inactive nodes held at 0) by
  /// Jacobi-preconditioned conjugate gradients; the result is rounded to f32 (as stored) and
  /// added to every point's current fit. Returns the number of active nodes; *iterations the
  /// solver steps taken.
  std::int64_t FitLevel(int level, double residual_threshold, std::int64_t max_nodes,
                        int* iterations);

  /// Mean |D - p| over the fitted targets (model units, every point counted once whatever its
  /// weight; the residual criterion and the budget's ranking use the weighted errors).
  double FitError() const;
  double EvalError() const;  ///< Mean |D - p| over the evaluated targets (0 if none).

  /// The last fitted level's active nodes of chart c: lattice indices (j + 1)(2^k + 3) + (i + 1),
  /// increasing, and their coefficients (model units, f32-exact).
  const std::vector<std::uint32_t>& nodes(std::size_t c) const { return charts_[c].nodes; }
  const std::vector<float>& values(std::size_t c) const { return charts_[c].values; }

 private:
  void LocateEntries();
  std::int64_t SelectNodes(double tau, std::int64_t max_nodes);
  void Prepare();
  void SampleValues(const std::vector<double>& xw);
  void Apply(const std::vector<double>& x, std::vector<double>* y);
  void ScatterTransposed(const std::vector<Vec3>& g);
  void Solve(int* iterations);
  double LevelValue(std::size_t c, Vec2 z) const;
  void Update();

  struct Entry {
    std::uint32_t point = 0;  // position in fit_
    double psi = 0.0;
    Vec2 z{0.0};
    Vec3 a{0.0};  // sqrt(weight) psi N: the point's weight folded into its row
  };
  // A sample's cell at the current level and, when its 4 x 4 block touches an active node, the
  // block's first position in the window arrays.
  struct Block {
    std::int32_t base = -1;
    std::int32_t w = 0;
    std::int32_t i = 0, j = 0;
    float bs[4], bt[4];
  };
  // A chart's active nodes at the current level, inside a window of its lattice that holds them
  // with a margin of 3 (so every block touching one lies inside it).
  struct Chart {
    int i0 = 0, j0 = 0, w = 0, h = 0;
    std::int64_t window = 0;  // first position in the window arrays
    std::int64_t first = 0;   // first unknown
    double lambda = 0.0;
    std::vector<std::uint32_t> nodes;
    std::vector<float> values;
  };

  const std::vector<double>& half_;
  const std::vector<DisplacementTarget>& targets_;
  std::vector<std::uint32_t> fit_, eval_;
  LevelFitOptions opt_;
  std::vector<Vec3> f_, target_;  // per target: sum_j a_j d_j so far, and delta sum_j a_j
  std::vector<std::int64_t> chart_begin_;
  std::vector<Entry> entries_;               // samples of the fitted points, chart by chart
  std::vector<std::int64_t> point_entries_;  // per fitted point its entries, -1 after the last
  int m_ = 1, stride_ = 4;
  std::vector<Chart> charts_;
  std::vector<Block> blocks_;
  std::int64_t unknowns_ = 0, window_size_ = 0;
  std::vector<std::int32_t> active_pos_;    // per unknown: its position in the windows
  std::vector<std::int32_t> active_chart_;  // per unknown: its chart
  std::vector<std::uint32_t> active_node_;  // per unknown: its lattice index
  std::vector<double> diag_, x_, xw_, yw_, v_, r2_;
  std::vector<double> cur_;  // per entry: its chart's displacement so far at the sample
  const std::vector<double>* own_ = nullptr;  // per entry: the consistency term's value
  std::vector<Vec3> g_;
};

}  // namespace dermis

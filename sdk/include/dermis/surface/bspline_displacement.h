// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Multilevel uniform cubic B-spline displacement functions, one per chart (paper Eq. 3,
/// section 5 "multi-level representations"; docs/notes/fit.md section 1).
///
/// Chart v's function lives on the square [-R_v, R_v]^2 of chart coordinates. Level k (0-based)
/// has 2^k cells per side and a (2^k + 3)^2 lattice of nodes. Two storage forms:
///
/// - **merged** (.dsurf version 1): level k's lattice is dense and stores the merged function
///   Psi_k = sum of the fitted levels 0..k (refined to level k), so evaluating with any number
///   of levels reads the 16 coefficients of one lattice (docs/notes/fit.md section 1, option (b)).
/// - **additive** (.dsurf version 3, docs/fitting.md "Adaptive displacement levels"): level k
///   stores only its own correction Phi_k, and only on the nodes the fit activated (the others
///   are 0); evaluating with L levels sums Phi_0 .. Phi_{L-1}. A level whose every node is
///   active is stored densely without a node list.
///
/// In both forms evaluating with L levels gives exactly the function of an L-level fit (runtime
/// level of detail by truncation).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/surface/displacement.h"

namespace dermis {

/// Number of nodes of one level-k lattice: (2^k + 3)^2.
constexpr std::int64_t BsplineLatticeSize(int level) {
  return ((std::int64_t{1} << level) + 3) * ((std::int64_t{1} << level) + 3);
}

/// Largest number of levels a chart may have (level 12 is a 4099^2 lattice).
constexpr int kMaxBsplineLevels = 13;

/// How the levels of a BsplineDisplacementData combine (see the file comment).
enum class BsplineLevelForm : std::uint8_t {
  kMerged = 0,    ///< Dense merged lattices; L levels read lattice L - 1.
  kAdditive = 1,  ///< Per-level corrections on active nodes; L levels sum levels 0..L-1.
};

/// The stored form of a BsplineDisplacement (what a .dsurf file holds).
struct BsplineDisplacementData {
  BsplineLevelForm form = BsplineLevelForm::kMerged;
  /// Per chart: half side R of the chart's square domain, > 0, in chart units.
  std::vector<double> half_extent;
  /// Per chart: number of levels, 0..kMaxBsplineLevels. 0 means d = 0 on that chart.
  std::vector<std::uint8_t> num_levels;
  /// Per chart: index into `values` of its level-0 coefficients; the chart's levels follow one
  /// another. One entry per chart plus a final one equal to values.size().
  std::vector<std::int64_t> offsets;
  /// kAdditive only (empty for kMerged): per level of every chart (chart 0's levels 0..L-1,
  /// then chart 1's, ...), the number of coefficients stored for it. BsplineLatticeSize(k)
  /// means dense (every node, in lattice order); fewer means sparse: the level's nodes are
  /// listed in `nodes`; 0 means the level adds nothing to that chart.
  std::vector<std::int32_t> level_counts;
  /// kAdditive only: the node indices of the sparse levels, level after level in the order of
  /// level_counts, strictly increasing within a level. Node (i, j), i, j = -1 .. 2^k + 1, has
  /// index (j + 1)(2^k + 3) + (i + 1); i runs along chart x.
  std::vector<std::uint32_t> nodes;
  /// Coefficients (model units). A dense level is row-major in node index order; a sparse one
  /// holds one value per listed node.
  std::vector<float> values;
};

/// Checks sizes, offsets, node lists and finiteness of `data` for `num_charts` charts.
Status ValidateBsplineDisplacementData(const BsplineDisplacementData& data,
                                       std::int64_t num_charts);

/// Immutable multilevel B-spline displacement; Evaluate() uses every level. Thread-safe,
/// no allocation after Create().
class BsplineDisplacement final : public Displacement {
 public:
  /// Validates and takes `data`. Returns null and sets *status on failure.
  static std::unique_ptr<BsplineDisplacement> Create(BsplineDisplacementData data,
                                                     std::int64_t num_charts, Status* status);

  void Evaluate(Index vertex, Vec2 z, double* value, Vec2* gradient) const override;

  /// Evaluates with only the first `levels` levels (0 gives d = 0; more than a chart has uses
  /// all of its levels). Outside its square a chart's function is evaluated at the nearest
  /// point of the square (constant extension) and the gradient is that of the clamped point.
  void EvaluateLevels(Index vertex, Vec2 z, int levels, double* value, Vec2* gradient) const;

  const BsplineDisplacementData& data() const { return data_; }
  /// The largest number of levels of any chart.
  int max_levels() const { return max_levels_; }
  /// Total number of stored coefficients.
  std::int64_t num_coefficients() const { return static_cast<std::int64_t>(data_.values.size()); }
  /// Stored coefficients of level `level` over all charts (0 beyond the deepest chart).
  std::int64_t level_coefficients(int level) const;
  /// Bytes held (stored data and the derived index).
  std::size_t memory_bytes() const;

 private:
  BsplineDisplacement() = default;
  // Adds the value and chart-space gradient of one lattice at z to *f, *fx, *fy.
  void AddLevel(std::size_t level_index, int level, double half_extent, Vec2 z, double* f,
                double* fx, double* fy) const;

  BsplineDisplacementData data_;
  int max_levels_ = 0;
  // Derived index (kAdditive): per chart, its first entry in the per-level arrays; per level,
  // its first value, its first node (-1: dense) and its first row in row_start_ (the sparse
  // level's nodes of lattice row r are nodes[node_begin + row_start_[row + r] ..
  // node_begin + row_start_[row + r + 1]); -1: no row table, for a level with fewer nodes
  // than its lattice has rows, whose nodes are searched whole: the table would outweigh them).
  std::vector<std::int64_t> chart_level_;
  std::vector<std::int64_t> level_value_, level_node_, level_row_;
  std::vector<std::int32_t> row_start_;
};

/// A view of a BsplineDisplacement truncated to its first `levels` levels (runtime level of
/// detail). Does not own `source`, which must outlive it.
class TruncatedDisplacement final : public Displacement {
 public:
  TruncatedDisplacement(const BsplineDisplacement* source, int levels)
      : source_(source), levels_(levels) {}
  void Evaluate(Index vertex, Vec2 z, double* value, Vec2* gradient) const override {
    source_->EvaluateLevels(vertex, z, levels_, value, gradient);
  }

 private:
  const BsplineDisplacement* source_;
  int levels_;
};

/// Uniform cubic B-spline basis on a cell, t in [0, 1]: b[k] = B_k(t), db[k] = B_k'(t).
void CubicBsplineBasis(double t, double b[4], double db[4]);

/// Cell index and local parameter of lattice coordinate x in [0, m] (m cells): i = floor(x)
/// clamped to m - 1, t = x - i in [0, 1].
void BsplineCell(double x, int m, int* i, double* t);

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Multilevel uniform cubic B-spline displacement functions, one per chart (paper Eq. 3,
/// section 5 "multi-level representations"; docs/notes/fit.md section 1).
///
/// Chart v's function lives on the square [-R_v, R_v]^2 of chart coordinates. Level k (0-based)
/// has 2^k cells per side and a (2^k + 3)^2 lattice of coefficients. Level k's lattice stores
/// the *merged* function Psi_k = sum of the fitted levels 0..k (refined to level k), so
/// evaluating with any number of levels costs 16 reads, and level-of-detail switching is a
/// choice of lattice (docs/notes/fit.md section 1, storage option (b)).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/surface/displacement.h"

namespace dermis {

/// Number of coefficients of one level-k lattice: (2^k + 3)^2.
constexpr std::int64_t BsplineLatticeSize(int level) {
  return ((std::int64_t{1} << level) + 3) * ((std::int64_t{1} << level) + 3);
}

/// Largest number of levels a chart may have (level 12 is a 4099^2 lattice).
constexpr int kMaxBsplineLevels = 13;

/// The stored form of a BsplineDisplacement (what a .dsurf file holds).
struct BsplineDisplacementData {
  /// Per chart: half side R of the chart's square domain, > 0, in chart units.
  std::vector<double> half_extent;
  /// Per chart: number of levels, 0..kMaxBsplineLevels. 0 means d = 0 on that chart.
  std::vector<std::uint8_t> num_levels;
  /// Per chart: index into `values` of its level-0 lattice; the chart's levels follow one
  /// another. One entry per chart plus a final one equal to values.size().
  std::vector<std::int64_t> offsets;
  /// Lattice coefficients (model units). Level k of a chart is row-major: node (i, j),
  /// i, j = -1 .. 2^k + 1, at (j + 1) * (2^k + 3) + (i + 1); i runs along chart x.
  std::vector<float> values;
};

/// Checks sizes, offsets and finiteness of `data` for `num_charts` charts.
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

 private:
  BsplineDisplacement() = default;
  BsplineDisplacementData data_;
  int max_levels_ = 0;
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

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Evaluation of multilevel cubic B-spline displacements (Lee, Wolberg and Shin 1997, as used by
// Yoon section 4-5; docs/notes/fit.md section 1: basis, lattice indexing, per-level storage).
#include "dermis/surface/bspline_displacement.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace dermis {

void CubicBsplineBasis(double t, double b[4], double db[4]) {
  const double s = 1.0 - t;
  const double t2 = t * t, t3 = t2 * t;
  b[0] = s * s * s / 6.0;
  b[1] = (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0;
  b[2] = (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0;
  b[3] = t3 / 6.0;
  db[0] = -0.5 * s * s;
  db[1] = 1.5 * t2 - 2.0 * t;
  db[2] = -1.5 * t2 + t + 0.5;
  db[3] = 0.5 * t2;
}

void BsplineCell(double x, int m, int* i, double* t) {
  x = std::min(std::max(x, 0.0), static_cast<double>(m));
  int c = static_cast<int>(std::floor(x));
  if (c > m - 1) c = m - 1;
  *i = c;
  *t = x - c;
}

Status ValidateBsplineDisplacementData(const BsplineDisplacementData& d, std::int64_t num_charts) {
  const auto n = static_cast<std::size_t>(num_charts);
  if (d.half_extent.size() != n || d.num_levels.size() != n || d.offsets.size() != n + 1) {
    return Status::InvalidInput(
        "displacement: expected " + std::to_string(num_charts) + " charts, got " +
        std::to_string(d.half_extent.size()) + " extents, " + std::to_string(d.num_levels.size()) +
        " level counts and " + std::to_string(d.offsets.size()) + " offsets");
  }
  if (!d.offsets.empty() && d.offsets[0] != 0) {
    return Status::InvalidInput("displacement: first lattice offset is not 0");
  }
  for (std::size_t c = 0; c < n; ++c) {
    const std::string name = "displacement of chart " + std::to_string(c);
    if (!(d.half_extent[c] > 0.0) || !std::isfinite(d.half_extent[c])) {
      return Status::InvalidInput(name + ": half extent is not a positive finite number");
    }
    if (d.num_levels[c] > kMaxBsplineLevels) {
      return Status::InvalidInput(name + ": " + std::to_string(d.num_levels[c]) +
                                  " levels, at most " + std::to_string(kMaxBsplineLevels));
    }
    std::int64_t size = 0;
    for (int k = 0; k < d.num_levels[c]; ++k) size += BsplineLatticeSize(k);
    if (d.offsets[c + 1] - d.offsets[c] != size) {
      return Status::InvalidInput(name + ": lattice offsets do not match its level count");
    }
  }
  if (d.offsets[n] != static_cast<std::int64_t>(d.values.size())) {
    return Status::InvalidInput("displacement: coefficient count does not match the offsets");
  }
  for (std::size_t i = 0; i < d.values.size(); ++i) {
    if (!std::isfinite(d.values[i])) {
      return Status::InvalidInput("displacement: coefficient " + std::to_string(i) +
                                  " is not finite");
    }
  }
  return Status::Ok();
}

std::unique_ptr<BsplineDisplacement> BsplineDisplacement::Create(BsplineDisplacementData data,
                                                                 std::int64_t num_charts,
                                                                 Status* status) {
  *status = ValidateBsplineDisplacementData(data, num_charts);
  if (!status->ok()) return nullptr;
  std::unique_ptr<BsplineDisplacement> d(new BsplineDisplacement());
  for (std::uint8_t levels : data.num_levels)
    d->max_levels_ = std::max<int>(d->max_levels_, levels);
  d->data_ = std::move(data);
  return d;
}

void BsplineDisplacement::Evaluate(Index vertex, Vec2 z, double* value, Vec2* gradient) const {
  EvaluateLevels(vertex, z, kMaxBsplineLevels, value, gradient);
}

void BsplineDisplacement::EvaluateLevels(Index vertex, Vec2 z, int levels, double* value,
                                         Vec2* gradient) const {
  const int available = data_.num_levels[static_cast<std::size_t>(vertex)];
  const int level = std::min(levels, available) - 1;
  if (level < 0) {
    *value = 0.0;
    *gradient = Vec2(0.0);
    return;
  }
  const double r = data_.half_extent[static_cast<std::size_t>(vertex)];
  const int m = 1 << level;
  const double scale = m / (2.0 * r);
  int i = 0, j = 0;
  double s = 0.0, t = 0.0;
  BsplineCell((z.x + r) * scale, m, &i, &s);
  BsplineCell((z.y + r) * scale, m, &j, &t);
  double bs[4], dbs[4], bt[4], dbt[4];
  CubicBsplineBasis(s, bs, dbs);
  CubicBsplineBasis(t, bt, dbt);
  std::int64_t offset = data_.offsets[static_cast<std::size_t>(vertex)];
  for (int k = 0; k < level; ++k) offset += BsplineLatticeSize(k);
  const int stride = m + 3;
  const float* lattice = data_.values.data() + offset;
  double f = 0.0, fx = 0.0, fy = 0.0;
  for (int l = 0; l < 4; ++l) {
    const float* row = lattice + static_cast<std::int64_t>(j + l) * stride + i;
    double a = 0.0, da = 0.0;
    for (int k = 0; k < 4; ++k) {
      a += bs[k] * row[k];
      da += dbs[k] * row[k];
    }
    f += bt[l] * a;
    fx += bt[l] * da;
    fy += dbt[l] * a;
  }
  *value = f;
  *gradient = Vec2(fx * scale, fy * scale);
}

}  // namespace dermis

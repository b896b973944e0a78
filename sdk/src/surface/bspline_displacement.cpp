// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Evaluation of multilevel cubic B-spline displacements (Lee, Wolberg and Shin 1997, as used by
// Yoon section 4-5; docs/notes/fit.md section 1: basis, lattice indexing, per-level storage), in
// the merged dense form of .dsurf version 1 and the additive sparse form of version 3
// (docs/fitting.md, "Adaptive displacement levels").
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

namespace {

Status CheckAdditiveLevels(const BsplineDisplacementData& d, std::size_t n) {
  std::size_t total_levels = 0;
  for (std::size_t c = 0; c < n; ++c) total_levels += d.num_levels[c];
  if (d.level_counts.size() != total_levels) {
    return Status::InvalidInput("displacement: expected " + std::to_string(total_levels) +
                                " level coefficient counts, got " +
                                std::to_string(d.level_counts.size()));
  }
  std::size_t g = 0, node = 0;
  for (std::size_t c = 0; c < n; ++c) {
    const std::string name = "displacement of chart " + std::to_string(c);
    std::int64_t chart_values = 0;
    for (int k = 0; k < d.num_levels[c]; ++k, ++g) {
      const std::int64_t size = BsplineLatticeSize(k);
      const std::int32_t count = d.level_counts[g];
      if (count < 0 || count > size) {
        return Status::InvalidInput(name + ", level " + std::to_string(k) + ": " +
                                    std::to_string(count) + " coefficients for a lattice of " +
                                    std::to_string(size) + " nodes");
      }
      chart_values += count;
      if (count == size) continue;  // dense: no node list
      if (d.nodes.size() - node < static_cast<std::size_t>(count)) {
        return Status::InvalidInput(name + ": the node lists end early");
      }
      for (std::int32_t i = 0; i < count; ++i, ++node) {
        if (d.nodes[node] >= static_cast<std::uint64_t>(size) ||
            (i > 0 && d.nodes[node] <= d.nodes[node - 1])) {
          return Status::InvalidInput(name + ", level " + std::to_string(k) +
                                      ": node indices out of range or not increasing");
        }
      }
    }
    if (d.offsets[c + 1] - d.offsets[c] != chart_values) {
      return Status::InvalidInput(name + ": lattice offsets do not match its level counts");
    }
  }
  if (node != d.nodes.size()) {
    return Status::InvalidInput("displacement: " + std::to_string(d.nodes.size() - node) +
                                " node indices belong to no level");
  }
  return Status::Ok();
}

}  // namespace

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
  if (d.form != BsplineLevelForm::kMerged && d.form != BsplineLevelForm::kAdditive) {
    return Status::InvalidInput("displacement: unknown level form");
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
    if (d.offsets[c + 1] < d.offsets[c]) {
      return Status::InvalidInput(name + ": lattice offsets decrease");
    }
    if (d.form == BsplineLevelForm::kMerged) {
      std::int64_t size = 0;
      for (int k = 0; k < d.num_levels[c]; ++k) size += BsplineLatticeSize(k);
      if (d.offsets[c + 1] - d.offsets[c] != size) {
        return Status::InvalidInput(name + ": lattice offsets do not match its level count");
      }
    }
  }
  if (d.form == BsplineLevelForm::kMerged) {
    if (!d.level_counts.empty() || !d.nodes.empty()) {
      return Status::InvalidInput("displacement: merged lattices have no node lists");
    }
  } else {
    Status s = CheckAdditiveLevels(d, n);
    if (!s.ok()) return s;
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
  if (data.form == BsplineLevelForm::kAdditive) {
    const std::size_t n = data.num_levels.size();
    d->chart_level_.assign(n + 1, 0);
    for (std::size_t c = 0; c < n; ++c)
      d->chart_level_[c + 1] = d->chart_level_[c] + data.num_levels[c];
    const auto total = static_cast<std::size_t>(d->chart_level_[n]);
    d->level_value_.resize(total);
    d->level_node_.resize(total);
    d->level_row_.resize(total);
    std::int64_t node = 0;
    for (std::size_t c = 0; c < n; ++c) {
      std::int64_t value = data.offsets[c];
      for (int k = 0; k < data.num_levels[c]; ++k) {
        const auto g = static_cast<std::size_t>(d->chart_level_[c] + k);
        const std::int32_t count = data.level_counts[g];
        d->level_value_[g] = value;
        value += count;
        d->level_row_[g] = static_cast<std::int64_t>(d->row_start_.size());
        if (count == BsplineLatticeSize(k)) {
          d->level_node_[g] = -1;
          continue;
        }
        // Row table of a sparse level: rows+1 starts relative to its first node; none for a
        // level with fewer nodes than rows (a fine level of a few nodes near a crease would
        // otherwise cost 4 (2^k + 4) bytes for them).
        d->level_node_[g] = node;
        const std::int64_t stride = (std::int64_t{1} << k) + 3;
        if (count < stride) {
          d->level_row_[g] = -1;
          node += count;
          continue;
        }
        std::int32_t at = 0;
        for (std::int64_t row = 0; row <= stride; ++row) {
          while (at < count &&
                 static_cast<std::int64_t>(data.nodes[static_cast<std::size_t>(node + at)]) <
                     row * stride) {
            ++at;
          }
          d->row_start_.push_back(at);
        }
        node += count;
      }
    }
  }
  d->data_ = std::move(data);
  return d;
}

std::int64_t BsplineDisplacement::level_coefficients(int level) const {
  std::int64_t total = 0;
  for (std::size_t c = 0; c < data_.num_levels.size(); ++c) {
    if (level >= data_.num_levels[c]) continue;
    if (data_.form == BsplineLevelForm::kMerged) {
      total += BsplineLatticeSize(level);
    } else {
      total += data_.level_counts[static_cast<std::size_t>(chart_level_[c] + level)];
    }
  }
  return total;
}

void BsplineDisplacement::Evaluate(Index vertex, Vec2 z, double* value, Vec2* gradient) const {
  EvaluateLevels(vertex, z, kMaxBsplineLevels, value, gradient);
}

void BsplineDisplacement::AddLevel(std::size_t g, int level, double r, Vec2 z, double* f,
                                   double* fx, double* fy) const {
  const int m = 1 << level;
  const double scale = m / (2.0 * r);
  int i = 0, j = 0;
  double s = 0.0, t = 0.0;
  BsplineCell((z.x + r) * scale, m, &i, &s);
  BsplineCell((z.y + r) * scale, m, &j, &t);
  double bs[4], dbs[4], bt[4], dbt[4];
  CubicBsplineBasis(s, bs, dbs);
  CubicBsplineBasis(t, bt, dbt);
  const int stride = m + 3;
  const float* values = data_.values.data() + level_value_[g];
  double v = 0.0, vx = 0.0, vy = 0.0;
  if (level_node_[g] < 0) {  // dense
    for (int l = 0; l < 4; ++l) {
      const float* row = values + static_cast<std::int64_t>(j + l) * stride + i;
      double a = 0.0, da = 0.0;
      for (int k = 0; k < 4; ++k) {
        a += bs[k] * row[k];
        da += dbs[k] * row[k];
      }
      v += bt[l] * a;
      vx += bt[l] * da;
      vy += dbt[l] * a;
    }
  } else {  // sparse: the listed nodes of rows j..j+3, columns i..i+3
    const std::uint32_t* nodes = data_.nodes.data() + level_node_[g];
    const std::int32_t* rows = level_row_[g] >= 0 ? row_start_.data() + level_row_[g] : nullptr;
    const std::uint32_t* end = nodes + data_.level_counts[g];
    for (int l = 0; l < 4; ++l) {
      const int row = j + l;
      const auto first = static_cast<std::uint32_t>(row * stride + i);
      const std::uint32_t* b = rows ? nodes + rows[row] : nodes;
      const std::uint32_t* e = rows ? nodes + rows[row + 1] : end;
      b = std::lower_bound(b, e, first);
      double a = 0.0, da = 0.0;
      for (; b != e && *b < first + 4; ++b) {
        const auto k = static_cast<int>(*b - first);
        const double x = values[b - nodes];
        a += bs[k] * x;
        da += dbs[k] * x;
      }
      v += bt[l] * a;
      vx += bt[l] * da;
      vy += dbt[l] * a;
    }
  }
  *f += v;
  *fx += vx * scale;
  *fy += vy * scale;
}

void BsplineDisplacement::EvaluateLevels(Index vertex, Vec2 z, int levels, double* value,
                                         Vec2* gradient) const {
  const auto c = static_cast<std::size_t>(vertex);
  const int use = std::min(levels, static_cast<int>(data_.num_levels[c]));
  double f = 0.0, fx = 0.0, fy = 0.0;
  const double r = data_.half_extent[c];
  if (use > 0 && data_.form == BsplineLevelForm::kMerged) {
    // The merged lattice of level use - 1 holds levels 0..use-1; evaluate it as a dense level.
    const int level = use - 1;
    const int m = 1 << level;
    const double scale = m / (2.0 * r);
    int i = 0, j = 0;
    double s = 0.0, t = 0.0;
    BsplineCell((z.x + r) * scale, m, &i, &s);
    BsplineCell((z.y + r) * scale, m, &j, &t);
    double bs[4], dbs[4], bt[4], dbt[4];
    CubicBsplineBasis(s, bs, dbs);
    CubicBsplineBasis(t, bt, dbt);
    std::int64_t offset = data_.offsets[c];
    for (int k = 0; k < level; ++k) offset += BsplineLatticeSize(k);
    const int stride = m + 3;
    const float* lattice = data_.values.data() + offset;
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
    fx *= scale;
    fy *= scale;
  } else {
    for (int k = 0; k < use; ++k) {
      const auto g = static_cast<std::size_t>(chart_level_[c] + k);
      if (data_.level_counts[g] == 0) continue;
      AddLevel(g, k, r, z, &f, &fx, &fy);
    }
  }
  *value = f;
  *gradient = Vec2(fx, fy);
}

std::size_t BsplineDisplacement::memory_bytes() const {
  const BsplineDisplacementData& d = data_;
  return sizeof(BsplineDisplacement) + d.half_extent.capacity() * sizeof(double) +
         d.num_levels.capacity() + d.offsets.capacity() * sizeof(std::int64_t) +
         d.level_counts.capacity() * sizeof(std::int32_t) +
         d.nodes.capacity() * sizeof(std::uint32_t) + d.values.capacity() * sizeof(float) +
         (chart_level_.capacity() + level_value_.capacity() + level_node_.capacity() +
          level_row_.capacity()) *
             sizeof(std::int64_t) +
         row_start_.capacity() * sizeof(std::int32_t);
}

}  // namespace dermis

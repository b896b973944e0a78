// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Displacements that vanish along a cut crease (docs/characters.md, "Hard edges cut open"):
// the displaced surface of Yoon Eq. 3 stays closed across the cut.
#include "dermis/offline/fit/seam_displacement.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

namespace dermis {
namespace {

// One level's nodes as (node index -> value), read from the stored form and written back.
struct Level {
  int m = 1;  // cells per side
  int stride = 4;
  std::map<std::uint32_t, double> changed;
  const float* dense = nullptr;          // dense storage, or
  const std::uint32_t* nodes = nullptr;  // sparse node list
  const float* values = nullptr;         // its values
  std::int32_t count = 0;
  double Get(int i, int j) const {
    const auto n = static_cast<std::uint32_t>(j * stride + i);
    const auto it = changed.find(n);
    if (it != changed.end()) return it->second;
    if (dense) return dense[n];
    const std::uint32_t* e = nodes + count;
    const std::uint32_t* p = std::lower_bound(nodes, e, n);
    return p != e && *p == n ? static_cast<double>(values[p - nodes]) : 0.0;
  }
  void Add(int i, int j, double delta) {
    if (delta == 0.0) return;
    const double v = Get(i, j) + delta;
    changed[static_cast<std::uint32_t>(j * stride + i)] = v;
  }
};

// The basis weights and first node of the lattice line through chart coordinate 0: cell
// `first` and weights w[0..3] of nodes first .. first + 3.
void LineThroughZero(int m, int* first, double w[4]) {
  double t = 0.0, dw[4];
  BsplineCell(0.5 * m, m, first, &t);
  CubicBsplineBasis(t, w, dw);
}

// Makes sum_l w[l] c(i, first + l) = 0 (rows == true: for each column i in [lo, hi]) or
// sum_l w[l] c(first + l, j) = 0 (for each row j in [lo, hi]) by the least change. Returns
// the largest residual before the change.
double Project(Level* level, bool rows, int lo, int hi, int first, const double w[4]) {
  double norm = 0.0, worst = 0.0;
  for (int l = 0; l < 4; ++l) norm += w[l] * w[l];
  for (int a = lo; a <= hi; ++a) {
    double g = 0.0;
    for (int l = 0; l < 4; ++l) {
      if (w[l] == 0.0) continue;
      g += w[l] * (rows ? level->Get(a, first + l) : level->Get(first + l, a));
    }
    worst = std::max(worst, std::abs(g));
    if (g == 0.0) continue;
    for (int l = 0; l < 4; ++l) {
      if (w[l] == 0.0) continue;
      if (rows) {
        level->Add(a, first + l, -w[l] * g / norm);
      } else {
        level->Add(first + l, a, -w[l] * g / norm);
      }
    }
  }
  return worst;
}

}  // namespace

Status ZeroDisplacementOnSeams(const ManifoldDomain& domain, const std::vector<std::uint8_t>& seam,
                               BsplineDisplacementData* data, std::int64_t* nodes_added) {
  const std::size_t nc = data->num_levels.size();
  if (data->form != BsplineLevelForm::kAdditive) {
    return Status::InvalidInput("seam displacement: the levels must be additive");
  }
  if (nc != static_cast<std::size_t>(domain.num_vertices())) {
    return Status::InvalidInput("seam displacement: " + std::to_string(nc) + " charts for " +
                                std::to_string(domain.num_vertices()) + " vertices");
  }
  if (seam.size() != nc) {
    return Status::InvalidInput("seam displacement: " + std::to_string(seam.size()) +
                                " seam marks for " + std::to_string(nc) + " charts");
  }
  Status valid = ValidateBsplineDisplacementData(*data, static_cast<std::int64_t>(nc));
  if (!valid.ok()) return Status::InvalidInput("seam displacement: " + valid.message());
  BsplineDisplacementData out;
  out.form = data->form;
  out.half_extent = data->half_extent;
  out.num_levels = data->num_levels;
  out.offsets.assign(nc + 1, 0);
  std::int64_t added = 0;
  std::size_t lc = 0, node_pos = 0;
  std::int64_t value_pos = 0;
  for (std::size_t c = 0; c < nc; ++c) {
    out.offsets[c] = static_cast<std::int64_t>(out.values.size());
    const bool on_seam = c < seam.size() && seam[c] != 0;
    const VertexKind kind = domain.chart(static_cast<Index>(c)).kind;
    for (int k = 0; k < data->num_levels[c]; ++k, ++lc) {
      const std::int64_t lattice = BsplineLatticeSize(k);
      const std::int32_t count = data->level_counts[lc];
      const bool dense = count == lattice;
      Level level;
      level.m = 1 << k;
      level.stride = level.m + 3;
      level.count = count;
      if (dense) {
        level.dense = data->values.data() + value_pos;
      } else {
        level.nodes = data->nodes.data() + node_pos;
        level.values = data->values.data() + value_pos;
      }
      if (on_seam && kind != VertexKind::kInterior && count > 0) {
        int first = 0;
        double w[4];
        LineThroughZero(level.m, &first, w);
        const int last = level.m + 2;  // the last node column (row)
        // The rays' node columns (rows): x >= 0 reaches columns first .. last, x <= 0 columns
        // 0 .. first + 2 (first + 3 at level 0, where the line is inside a cell).
        if (kind == VertexKind::kCrease) {
          Project(&level, true, 0, last, first, w);
        } else {
          const bool up = kind == VertexKind::kConvexCorner;  // the second ray: +y or -y
          // The two sets share only the nodes round the origin: the alternation converges
          // fast; it stops once both residuals are below 1e-14 of the first.
          double scale = 0.0;
          for (int it = 0; it < 100; ++it) {
            const double a = Project(&level, true, first, last, first, w);
            // y <= 0 reaches the rows up to the last one whose basis is non-zero at 0.
            const int below = std::min(first + (w[3] != 0.0 ? 3 : 2), last);
            const double b = up ? Project(&level, false, first, last, first, w)
                                : Project(&level, false, 0, below, first, w);
            if (it == 0) scale = std::max(a, b);
            if (!(std::max(a, b) > 1e-14 * scale)) break;
          }
        }
      }
      // Write the level back: dense as it was, sparse with the new non-zero nodes merged in.
      if (dense || level.changed.empty()) {
        for (std::int32_t n = 0; n < count; ++n) {
          const auto node = dense ? static_cast<std::uint32_t>(n) : level.nodes[n];
          const auto it = level.changed.find(node);
          out.values.push_back(it != level.changed.end()
                                   ? static_cast<float>(it->second)
                                   : (dense ? level.dense[n] : level.values[n]));
          if (!dense) out.nodes.push_back(node);
        }
        out.level_counts.push_back(count);
      } else {
        std::map<std::uint32_t, float> merged;
        for (std::int32_t n = 0; n < count; ++n) merged[level.nodes[n]] = level.values[n];
        for (const auto& [node, v] : level.changed) {
          if (merged.count(node) == 0 && static_cast<float>(v) == 0.0f) continue;
          added += merged.count(node) == 0 ? 1 : 0;
          merged[node] = static_cast<float>(v);
        }
        if (static_cast<std::int64_t>(merged.size()) == lattice) {
          for (const auto& [node, v] : merged) out.values.push_back(v);
        } else {
          for (const auto& [node, v] : merged) {
            out.nodes.push_back(node);
            out.values.push_back(v);
          }
        }
        out.level_counts.push_back(static_cast<std::int32_t>(merged.size()));
      }
      value_pos += count;
      if (!dense) node_pos += static_cast<std::size_t>(count);
    }
  }
  out.offsets[nc] = static_cast<std::int64_t>(out.values.size());
  Status s = ValidateBsplineDisplacementData(out, static_cast<std::int64_t>(nc));
  if (!s.ok()) return Status::Internal("seam displacement: " + s.message());
  *data = std::move(out);
  if (nodes_added) *nodes_added = added;
  return Status::Ok();
}

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The check points' shading rule (docs/characters.md, "Levels checked by the shading"). The
// surface's normal is that of the displaced surface, paper Eq. 3-4 (EvaluateSurface); each
// level's share is read through TruncatedDisplacement, the runtime's level of detail.
#include "dermis/offline/fit/shading_check.h"

#include <algorithm>
#include <cmath>

#include "dermis/core/parallel.h"
#include "dermis/surface/surface_evaluator.h"

namespace dermis {

std::vector<double> CheckPointNormalAngles(const ManifoldDomain& domain, const LocalPatch* patches,
                                           const BsplineDisplacement& displacement,
                                           const std::vector<PointFit>& fits,
                                           const std::vector<Vec3>& normals, int threads) {
  const int levels = displacement.max_levels();
  std::vector<double> out(static_cast<std::size_t>(levels) + 1, 0.0);
  const std::size_t n = std::min(fits.size(), normals.size());
  if (n == 0) return out;
  // Per point and level count its angle (-1: left out), then summed in point order.
  const std::size_t stride = out.size();
  std::vector<double> angle(n * stride, -1.0);
  ParallelFor(std::max(threads, 1), n, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const PointFit& f = fits[i];
      const double ln = glm::length(normals[i]);
      if (f.status != PointFitStatus::kOptimized || !(ln > 0.0) || !std::isfinite(ln)) continue;
      for (int l = 0; l <= levels; ++l) {
        const TruncatedDisplacement view(&displacement, l);
        SurfacePoint sp;
        if (!EvaluateSurface(domain, patches, l == 0 ? nullptr : &view, f.face, f.uv, &sp)) {
          break;
        }
        const double c = std::min(1.0, std::abs(glm::dot(sp.normal, normals[i])) / ln);
        angle[i * stride + static_cast<std::size_t>(l)] = std::acos(c);
      }
    }
  });
  for (std::size_t l = 0; l < stride; ++l) {
    double sum = 0.0, count = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double a = angle[i * stride + l];
      if (a < 0.0) continue;
      sum += a, count += 1.0;
    }
    out[l] = count > 0.0 ? sum / count : 0.0;
  }
  return out;
}

int ShadingCheckLevels(const std::vector<double>& angles, double tolerance) {
  if (angles.empty()) return 0;
  int keep = static_cast<int>(angles.size()) - 1;
  while (keep > 0 && angles[static_cast<std::size_t>(keep)] >
                         (1.0 + tolerance) * angles[static_cast<std::size_t>(keep - 1)]) {
    --keep;
  }
  return keep;
}

BsplineDisplacementData TruncateBsplineLevels(const BsplineDisplacementData& data, int levels) {
  if (data.form != BsplineLevelForm::kAdditive) return data;
  levels = std::max(levels, 0);
  bool deeper = false;
  for (std::uint8_t l : data.num_levels) deeper = deeper || l > levels;
  if (!deeper) return data;
  BsplineDisplacementData out;
  out.form = data.form;
  out.half_extent = data.half_extent;
  const std::size_t nc = data.num_levels.size();
  out.num_levels.assign(nc, 0);
  out.offsets.assign(nc + 1, 0);
  std::size_t g = 0;     // the chart's first entry in level_counts
  std::size_t node = 0;  // its first listed node
  for (std::size_t c = 0; c < nc; ++c) {
    const int had = data.num_levels[c];
    // Its levels kept: at most `levels`, and up to the last with a coefficient.
    int keep = std::min(had, levels);
    while (keep > 0 && data.level_counts[g + static_cast<std::size_t>(keep) - 1] == 0) --keep;
    out.num_levels[c] = static_cast<std::uint8_t>(keep);
    out.offsets[c] = static_cast<std::int64_t>(out.values.size());
    std::int64_t value = data.offsets[c];
    for (int k = 0; k < had; ++k) {
      const std::int32_t count = data.level_counts[g + static_cast<std::size_t>(k)];
      const bool sparse = count != BsplineLatticeSize(k);
      if (k < keep) {
        out.level_counts.push_back(count);
        out.values.insert(out.values.end(), data.values.begin() + value,
                          data.values.begin() + value + count);
        if (sparse) {
          out.nodes.insert(out.nodes.end(), data.nodes.begin() + static_cast<std::ptrdiff_t>(node),
                           data.nodes.begin() + static_cast<std::ptrdiff_t>(node) + count);
        }
      }
      value += count;
      if (sparse) node += static_cast<std::size_t>(count);
    }
    g += static_cast<std::size_t>(had);
  }
  out.offsets[nc] = static_cast<std::int64_t>(out.values.size());
  return out;
}

}  // namespace dermis

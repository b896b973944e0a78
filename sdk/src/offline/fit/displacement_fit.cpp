// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Per-chart displacement fitting by multilevel B-spline approximation (Yoon section 4,
// "Optimal displacement function"; docs/notes/fit.md sections 1 and 6 for the domain and the level
// choice).
#include "dermis/offline/fit/displacement_fit.h"

#include <algorithm>
#include <cmath>

#include "dermis/core/parallel.h"
#include "dermis/offline/fit/mba_fit.h"
#include "dermis/surface/blend.h"

namespace dermis {

double ChartHalfExtent(const ChartParams& chart, double blend_lb) {
  const double radius = std::sqrt(2.0) * (1.0 - blend_lb);
  return 1.02 * std::pow(radius, chart.p);
}

int ChooseLevels(std::size_t samples, const DisplacementFitOptions& options) {
  const int max_levels = std::clamp(options.max_levels, 1, kMaxBsplineLevels);
  if (samples == 0) return 0;
  if (options.density <= 0.0) return max_levels;
  // Level k has 2^k cells per side: the finest level is the first with 2^k >= density sqrt(n).
  const double cells = options.density * std::sqrt(static_cast<double>(samples));
  const int level = static_cast<int>(std::ceil(std::log2(std::max(cells, 1.0))));
  return std::clamp(level + 1, 1, max_levels);
}

void MakeDisplacementTargets(const ManifoldDomain& domain, const LocalPatch* patches,
                             const std::vector<PointFit>& fits,
                             std::vector<DisplacementTarget>* targets,
                             std::vector<std::size_t>* index) {
  targets->clear();
  if (index) index->clear();
  const MeshTopology& topo = domain.topology();
  const double lb = domain.options().blend_lb;
  const double ub = 1.0 - lb;
  for (std::size_t i = 0; i < fits.size(); ++i) {
    const PointFit& f = fits[i];
    if (f.status != PointFitStatus::kOptimized) continue;
    DisplacementTarget t;
    t.delta = f.delta;
    for (int a = 0; a < 4; ++a) {
      const Vec2 cd = FaceToCorner(a, f.uv);
      if (cd.x >= ub || cd.y >= ub) continue;
      const double psi = CornerWeight(domain.options().blend_type, lb, cd);
      if (!(psi > 0.0)) continue;
      const Index v = topo.face_vertex(f.face, a);
      const Vec2 z = domain.FaceToChart(f.face, a, f.uv);
      PatchFrame frame;
      EvaluatePatchFrame(patches[v], z, &frame);
      t.chart[t.count] = v;
      t.z[t.count] = z;
      t.a[t.count] = psi * frame.n;
      ++t.count;
    }
    if (t.count == 0) continue;
    targets->push_back(t);
    if (index) index->push_back(i);
  }
}

BsplineDisplacementData FitDisplacements(const ManifoldDomain& domain,
                                         const std::vector<ChartSample>& samples,
                                         const DisplacementFitOptions& options) {
  const Index num_charts = domain.num_vertices();
  // Stable counting sort of the samples by chart.
  std::vector<std::size_t> start(static_cast<std::size_t>(num_charts) + 1, 0);
  for (const ChartSample& s : samples) ++start[static_cast<std::size_t>(s.chart) + 1];
  for (Index c = 0; c < num_charts; ++c) start[c + 1] += start[c];
  std::vector<Vec2> z(samples.size());
  std::vector<double> values(samples.size());
  {
    std::vector<std::size_t> next(start.begin(), start.end() - 1);
    for (const ChartSample& s : samples) {
      const std::size_t k = next[static_cast<std::size_t>(s.chart)]++;
      z[k] = s.z;
      values[k] = s.value;
    }
  }
  BsplineDisplacementData data;
  data.half_extent.resize(num_charts);
  data.num_levels.resize(num_charts);
  std::vector<std::vector<double>> lattices(static_cast<std::size_t>(num_charts));
  ParallelFor(ResolveThreadCount(options.threads), static_cast<std::size_t>(num_charts),
              [&](std::size_t begin, std::size_t end) {
                for (std::size_t c = begin; c < end; ++c) {
                  const double r = ChartHalfExtent(domain.chart(static_cast<Index>(c)),
                                                   domain.options().blend_lb);
                  const std::size_t n = start[c + 1] - start[c];
                  const int levels = ChooseLevels(n, options);
                  data.half_extent[c] = r;
                  data.num_levels[c] = static_cast<std::uint8_t>(levels);
                  MbaOptions mba;
                  mba.finest_passes = options.finest_passes;
                  mba.smoothing = options.smoothing;
                  FitMultilevelBspline(z.data() + start[c], values.data() + start[c], n, r, levels,
                                       &lattices[c], nullptr, mba);
                }
              });
  data.offsets.assign(static_cast<std::size_t>(num_charts) + 1, 0);
  for (Index c = 0; c < num_charts; ++c) {
    data.offsets[c + 1] = data.offsets[c] + static_cast<std::int64_t>(lattices[c].size());
  }
  data.values.reserve(static_cast<std::size_t>(data.offsets.back()));
  for (const std::vector<double>& l : lattices) {
    for (double v : l) data.values.push_back(static_cast<float>(v));
  }
  return data;
}

}  // namespace dermis

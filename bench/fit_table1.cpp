// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Paper Table 1 (bunny row) side by side with ours: fits ../shared/data/scans/stanford-bunny.obj
// with 540 control vertices, reports the fit's own errors and timings, checks them
// independently against the level-16 tessellation (point-to-triangle distances), and checks
// that --threads 1 and 2 give the same .dsurf bytes.
// Usage (from the repo root): bench_fit [OBJ|PLY] [--control-vertices N] [--density D]
//                             [--repeat R]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "dermis/offline/point_input.h"
#include "dermis/offline/surface_fit.h"
#include "dermis/offline/triangle_distance.h"
#include "dermis/surface/dsurf.h"
#include "dermis/surface/tessellation.h"

using namespace dermis;

int main(int argc, char** argv) {
  std::string path = "../shared/data/scans/stanford-bunny.obj";
  int control_vertices = 540, repeat = 3;
  double density = -1.0;  // -1: FitOptions' default
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--control-vertices") == 0 && i + 1 < argc) {
      control_vertices = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--density") == 0 && i + 1 < argc) {
      density = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--repeat") == 0 && i + 1 < argc) {
      repeat = std::max(1, std::atoi(argv[++i]));
    } else {
      path = argv[i];
    }
  }
  if (!std::filesystem::exists(path)) {
    std::printf("bench_fit: skipped: %s not found (run from the repo root with ../shared/data)\n",
                path.c_str());
    return 0;
  }
  PolygonMesh mesh;
  Index dropped = 0;
  Status s = ReadFitInput(path, &mesh, &dropped);
  if (!s.ok()) {
    std::fprintf(stderr, "bench_fit: %s\n", s.message().c_str());
    return 1;
  }
  FitInput input;
  input.points = mesh.positions;
  input.mesh = &mesh;
  input.points_dropped = dropped;
  FitOptions options;
  options.control_vertices = control_vertices;
  if (density >= 0.0) options.displacement.density = density;
  std::vector<double> totals;
  FitReport report;
  FittedSurface fitted;
  std::string bytes_default;
  for (int r = 0; r < repeat; ++r) {
    s = FitSurface(input, options, &fitted, &report);
    if (!s.ok()) {
      std::fprintf(stderr, "bench_fit: %s\n", s.message().c_str());
      return 1;
    }
    totals.push_back(report.seconds.total);
  }
  std::sort(totals.begin(), totals.end());
  bytes_default = SerializeDsurf(*fitted.surface.domain, fitted.surface.control.positions.data(),
                                 fitted.displacement.get());
  // Independent check: fitted (not held-out) points against the level-16 tessellation.
  TessellationPattern pattern;
  TessellationPattern::Build(fitted.surface.domain->topology(), 16, &pattern);
  std::vector<Vec3> x(pattern.samples.size());
  EvaluateSamples(*fitted.surface.domain, fitted.surface.patches.data(), fitted.displacement.get(),
                  pattern.samples.data(), x.size(), x.data(), nullptr);
  TriangleDistanceTree tree;
  tree.Build(x, pattern.triangles);
  double sum = 0.0, mx = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < input.points.size(); ++i) {
    if (IsHeldOut(i, options.holdout, options.holdout_seed)) continue;
    const double d = tree.Query(input.points[i]).distance / report.scale;
    sum += d, mx = std::max(mx, d), ++n;
  }
  // Determinism across thread counts.
  bool identical = true;
  for (int threads : {1, 2}) {
    FitOptions o = options;
    o.threads = threads;
    FittedSurface f;
    FitReport rr;
    if (!FitSurface(input, o, &f, &rr).ok()) return 1;
    identical = identical && SerializeDsurf(*f.surface.domain, f.surface.control.positions.data(),
                                            f.displacement.get()) == bytes_default;
  }
  const FitErrors& e = report.error;
  std::printf("Yoon 2006 Table 1, bunny row, vs dermis (%s, %d threads, median of %d runs)\n",
              path.c_str(), report.threads, repeat);
  std::printf("| | paper | dermis |\n|---|---|---|\n");
  std::printf("| data points | 34,834 | %lld (%lld fitted, %lld held out, %lld outside) |\n",
              static_cast<long long>(report.points), static_cast<long long>(report.points_fitted),
              static_cast<long long>(report.points_holdout),
              static_cast<long long>(report.points_outside));
  std::printf("| control vertices | 540 | %lld (%lld quads) |\n",
              static_cast<long long>(report.control_vertices),
              static_cast<long long>(report.control_faces));
  std::printf("| control mesh (s) | (commercial tool) | %.3f |\n", report.seconds.control_mesh);
  std::printf("| projection and optimisation (s) | 221.07 | %.3f |\n",
              report.seconds.projection_optimization);
  std::printf("| displacement functions (s) | 1.43 | %.3f |\n", report.seconds.displacement);
  std::printf("| total fit (s) | 222.5 + control mesh | %.3f (min %.3f, max %.3f) |\n",
              totals[totals.size() / 2], totals.front(), totals.back());
  std::printf("| error without optimisation | 1.78e-3 | %.3g |\n", e.unoptimized_mean);
  std::printf("| error with optimisation (E1 mean) | 1.52e-4 | %.3g |\n", e.mean);
  std::printf("| E1 rms / max | - | %.3g / %.3g |\n", e.rms, e.max);
  std::printf("| held-out mean / max (E2) | - | %.3g / %.3g (%.2f x E1) |\n", e.holdout_mean,
              e.holdout_max, e.holdout_mean / e.mean);
  std::printf("| Hausdorff (E3) | - | %.3g (%.3f%% of diagonal) |\n", e.hausdorff,
              e.hausdorff_percent_diagonal);
  std::printf("| coefficients (all levels / finest) | - | %lld / %lld, %d levels |\n",
              static_cast<long long>(report.coefficients),
              static_cast<long long>(report.finest_coefficients), report.max_levels);
  std::printf("| metrics (s, not in total) | - | %.3f |\n", report.seconds.metrics);
  std::printf(
      "independent check: %zu fitted points vs level-16 tessellation (%zu triangles): "
      "mean %.3g (reported E1 %.3g: %s), max %.3g\n",
      n, pattern.triangles.size() / 3, sum / static_cast<double>(n), e.mean,
      sum / static_cast<double>(n) <= e.mean ? "within" : "ABOVE", mx);
  std::printf("threads 1 and 2 give identical .dsurf bytes (%zu bytes): %s\n", bytes_default.size(),
              identical ? "yes" : "NO");
  return 0;
}

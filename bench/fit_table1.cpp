// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Paper Table 1 (bunny row) side by side with ours: fits ../shared/data/scans/stanford-bunny.obj
// with 540 control vertices, reports the fit's own errors and timings, checks them
// independently against the level-16 tessellation (point-to-triangle distances), and checks
// that --threads 1 and 2 give the same .dsurf bytes.
// Usage (from the repo root): bench_fit [OBJ|PLY] [--control-vertices N] [--density D]
//                             [--control-fit ITERATIONS] [--finest-passes P] [--smoothing S]
//                             [--repeat R] [--detail] [--mba]
// --density, --finest-passes and --smoothing set the paper's per-chart MBA (--mba); the default
// displacement fit is the adaptive one (docs/fitting.md, "Adaptive displacement levels").
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "dermis/dsurf/dsurf.h"
#include "dermis/offline/fit/surface_fit.h"
#include "dermis/offline/fit/surface_projection.h"
#include "dermis/offline/geometry/triangle_distance.h"
#include "dermis/offline/io/point_input.h"
#include "dermis/surface/chart.h"
#include "dermis/surface/surface_evaluator.h"
#include "dermis/surface/tessellation.h"

using namespace dermis;

namespace {

// Distances from the points to the fitted surface tessellated at `level` (exact
// point-to-triangle distances), divided by `scale`.
std::vector<double> DistancesToTessellation(const FittedSurface& fitted, int level,
                                            const std::vector<Vec3>& points, double scale) {
  TessellationPattern pattern;
  TessellationPattern::Build(fitted.surface.domain->topology(), level, &pattern);
  std::vector<Vec3> x(pattern.samples.size());
  EvaluateSamples(*fitted.surface.domain, fitted.surface.patches.data(), fitted.displacement.get(),
                  pattern.samples.data(), x.size(), x.data(), nullptr);
  TriangleDistanceTree tree;
  tree.Build(x, pattern.triangles);
  std::vector<double> d(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) d[i] = tree.Query(points[i]).distance / scale;
  return d;
}

void PrintQuantiles(std::vector<double> v, const char* name) {
  std::sort(v.begin(), v.end());
  auto q = [&](double f) {
    return v[static_cast<std::size_t>(f * static_cast<double>(v.size() - 1))];
  };
  std::printf(
      "detail: %s quantiles 10%% %.3g, 50%% %.3g, 90%% %.3g, 99%% %.3g, 99.9%% %.3g, max %.3g\n",
      name, q(0.1), q(0.5), q(0.9), q(0.99), q(0.999), v.back());
}

// --detail: where the errors come from. `tess` holds the level-16 distance of each fitted point.
void PrintDetail(const FittedSurface& fitted, const PolygonMesh& mesh,
                 const std::vector<Vec3>& fit_points, const std::vector<double>& tess,
                 double scale) {
  const ManifoldDomain& domain = *fitted.surface.domain;
  const LocalPatch* patches = fitted.surface.patches.data();
  const Displacement* disp = fitted.displacement.get();
  const double count = static_cast<double>(fit_points.size());
  // Per status: E1 at the fitted parameter, true closest distance and level-16 distance; for
  // optimised points, the level-16 excess over the true distance by dominant-corner valence
  // and by distance to the face's edge.
  double se[3] = {0, 0, 0}, sc[3] = {0, 0, 0}, st[3] = {0, 0, 0}, cnt[3] = {0, 0, 0};
  double ex[16] = {0}, nx[16] = {0}, ebin[5] = {0}, nbin[5] = {0};
  std::vector<double> excess, e1s;
  for (std::size_t i = 0; i < fit_points.size(); ++i) {
    const PointFit& f = fitted.point_fits[i];
    const int k = static_cast<int>(f.status);
    st[k] += tess[i], cnt[k] += 1;
    if (f.status == PointFitStatus::kOutside) continue;
    SurfacePoint sp;
    EvaluateSurface(domain, patches, disp, f.face, f.uv, &sp);
    const double e = glm::length(sp.position - fit_points[i]) / scale;
    Index face = f.face;
    Vec2 uv = f.uv;
    const double c =
        ClosestPointOnSurface(domain, patches, disp, fit_points[i], &face, &uv) / scale;
    se[k] += e, sc[k] += c;
    if (f.status != PointFitStatus::kOptimized) continue;
    excess.push_back(tess[i] - c), e1s.push_back(e);
    const Index v = domain.topology().face_vertex(f.face, DominantCorner(f.uv));
    const int val = std::min(domain.topology().valence(v), 15);
    ex[val] += tess[i] - c, nx[val] += 1;
    const double edge = std::min(std::min(f.uv.x, 1.0 - f.uv.x), std::min(f.uv.y, 1.0 - f.uv.y));
    const int bin = std::min(4, static_cast<int>(edge / 0.1));
    ebin[bin] += tess[i] - c, nbin[bin] += 1;
  }
  const char* names[3] = {"optimized", "not converged", "outside"};
  for (int k = 0; k < 3; ++k) {
    std::printf(
        "detail: %-13s %6.0f points: sum E1 %.4g, sum closest %.4g, sum tess %.4g "
        "(per fitted point: %.3g / %.3g / %.3g)\n",
        names[k], cnt[k], se[k], sc[k], st[k], se[k] / (cnt[0] + cnt[1]), sc[k] / (cnt[0] + cnt[1]),
        st[k] / (cnt[0] + cnt[1]));
  }
  PrintQuantiles(e1s, "optimized E1");
  PrintQuantiles(excess, "optimized tess - closest");
  for (int k = 0; k < 16; ++k) {
    if (nx[k] > 0) {
      std::printf("detail: valence %d: %.0f points, mean tess excess %.3g\n", k, nx[k],
                  ex[k] / nx[k]);
    }
  }
  for (int b = 0; b < 5; ++b) {
    std::printf(
        "detail: distance to face edge %.1f..%.1f: %.0f points, mean tess excess %.3g, share of "
        "mean %.3g\n",
        0.1 * b, 0.1 * b + 0.1, nbin[b], ebin[b] / nbin[b], ebin[b] / count);
  }
  // Share of the means carried by the points above each threshold.
  for (double t : {1e-4, 3e-4, 1e-3, 3e-3}) {
    double st_hi = 0, se_hi = 0, n_hi = 0;
    for (double v : tess) {
      if (v > t) st_hi += v, n_hi += 1;
    }
    for (double v : e1s) {
      if (v > t) se_hi += v;
    }
    std::printf(
        "detail: above %.0e: tess %.0f points carry %.3g of the mean; optimized E1 above it "
        "carries %.3g\n",
        t, n_hi, st_hi / count, se_hi / count);
  }
  // Finer tessellations, and the surface (level 8) against the input triangles.
  for (int level : {32, 64}) {
    double sm = 0.0;
    for (double d : DistancesToTessellation(fitted, level, fit_points, scale)) sm += d;
    std::printf("detail: level %d tessellation: mean %.3g\n", level, sm / count);
  }
  TriangleDistanceTree data_tree;
  data_tree.Build(mesh.positions, TriangulateFan(mesh));
  TessellationPattern pattern;
  TessellationPattern::Build(domain.topology(), 8, &pattern);
  std::vector<Vec3> xs(pattern.samples.size());
  EvaluateSamples(domain, patches, disp, pattern.samples.data(), xs.size(), xs.data(), nullptr);
  std::vector<double> sd;
  for (const Vec3& p : xs) sd.push_back(data_tree.Query(p).distance / scale);
  PrintQuantiles(sd, "surface -> data (level 8)");
}

}  // namespace

int main(int argc, char** argv) {
  std::string path = "../shared/data/scans/stanford-bunny.obj";
  int control_vertices = 540, repeat = 3;
  bool detail = false, mba = false;
  double density = -1.0;    // -1: FitOptions' default
  int control_fit = -1;     // -1: FitOptions' default
  int finest_passes = -1;   // -1: FitOptions' default
  double smoothing = -1.0;  // -1: FitOptions' default
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--control-vertices") == 0 && i + 1 < argc) {
      control_vertices = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--density") == 0 && i + 1 < argc) {
      density = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--control-fit") == 0 && i + 1 < argc) {
      control_fit = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--finest-passes") == 0 && i + 1 < argc) {
      finest_passes = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--smoothing") == 0 && i + 1 < argc) {
      smoothing = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--mba") == 0) {
      mba = true;
    } else if (std::strcmp(argv[i], "--detail") == 0) {
      detail = true;
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
  if (control_fit >= 0) options.control_fit_iterations = control_fit;
  if (finest_passes >= 1) options.displacement.finest_passes = finest_passes;
  if (smoothing >= 0.0) options.displacement.smoothing = smoothing;
  if (mba) options.displacement.method = DisplacementMethod::kMba;
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
                                 fitted.displacement.get(), report.points);
  // Independent check: fitted (not held-out) points against the level-16 tessellation.
  std::vector<Vec3> fit_points;
  for (std::size_t i = 0; i < input.points.size(); ++i) {
    if (!IsHeldOut(i, options.holdout, options.holdout_seed)) fit_points.push_back(input.points[i]);
  }
  const std::vector<double> tess = DistancesToTessellation(fitted, 16, fit_points, report.scale);
  double sum = 0.0, mx = 0.0;
  for (double d : tess) sum += d, mx = std::max(mx, d);
  const std::size_t n = tess.size();
  if (detail) PrintDetail(fitted, mesh, fit_points, tess, report.scale);
  // Determinism across thread counts.
  bool identical = true;
  for (int threads : {1, 2}) {
    FitOptions o = options;
    o.threads = threads;
    FittedSurface f;
    FitReport rr;
    if (!FitSurface(input, o, &f, &rr).ok()) return 1;
    identical = identical && SerializeDsurf(*f.surface.domain, f.surface.control.positions.data(),
                                            f.displacement.get(), rr.points) == bytes_default;
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
  std::printf("| E1 closest-point mean (fitted points) | - | %.3g |\n", e.closest_mean);
  std::printf("| coefficients | - | %lld (%.2f per data point), %d levels |\n",
              static_cast<long long>(report.coefficients), report.coefficients_per_point,
              report.max_levels);
  std::printf("| coefficients per level | - |");
  for (std::size_t k = 0; k < report.level_coefficients.size(); ++k) {
    std::printf("%s%lld", k == 0 ? " " : ", ",
                static_cast<long long>(report.level_coefficients[k]));
  }
  std::printf(" |\n");
  std::printf("| metrics (s, not in total) | - | %.3f |\n", report.seconds.metrics);
  std::printf(
      "independent check: %zu fitted points vs level-16 tessellation (%zu triangles): "
      "mean %.3g (reported E1 %.3g: %s), max %.3g\n",
      n, static_cast<std::size_t>(fitted.surface.domain->num_faces()) * 16 * 16 * 2,
      sum / static_cast<double>(n), e.mean,
      sum / static_cast<double>(n) <= e.mean ? "within" : "ABOVE", mx);
  std::printf("threads 1 and 2 give identical .dsurf bytes (%zu bytes): %s\n", bytes_default.size(),
              identical ? "yes" : "NO");
  if (!report.displacement_fit.trial.empty()) {
    std::printf(
        "stopping rule (validation split of the fitted points, mean |D - p| in the unit "
        "above):\n");
    for (const AdaptiveLevelReport& lr : report.displacement_fit.trial) {
      std::printf("  level %d: %lld nodes, fitted %.3g, validation %.3g%s\n", lr.level,
                  static_cast<long long>(lr.nodes), lr.train_mean / report.scale,
                  lr.validation_mean / report.scale,
                  lr.level < report.displacement_fit.levels ? "" : "  (not kept)");
    }
    std::printf("  %d levels kept, stopped by: %s\n", report.displacement_fit.levels,
                report.displacement_fit.stopped_by.c_str());
  }
  return 0;
}

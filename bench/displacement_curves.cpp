// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Displacement functions against their size: fits the control mesh and the points' parameters
// once (FitSurface), then refits only the displacement functions with each setting given and
// prints E1 (fitted points, at their parameters), the held-out error (point to surface), the
// independent level-16 tessellation check, the coefficient count and the fit's seconds.
// docs/fitting.md, "Adaptive displacement levels" quotes its tables.
//
// Usage (from the repo root):
//   bench_displacement [OBJ|PLY] [--control-vertices N] [--control-mesh OBJ] [--threads T]
//                      [--no-tess] SETTING...
// SETTING: "adaptive:key=value,..." (keys: weight, residual, smoothing, validation,
//          improvement, iterations, levels), "mba:key=value,..." (density, passes, smoothing,
//          levels) or "curve:key=value,..." (the adaptive fit without the stopping rule at
//          1, 2, ... `levels` levels: the held-out error against the lattice size).
#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "dermis/offline/fit/displacement_fit.h"
#include "dermis/offline/fit/surface_fit.h"
#include "dermis/offline/fit/surface_projection.h"
#include "dermis/offline/geometry/triangle_distance.h"
#include "dermis/offline/io/obj_io.h"
#include "dermis/offline/io/point_input.h"
#include "dermis/surface/surface_evaluator.h"
#include "dermis/surface/tessellation.h"

using namespace dermis;

namespace {

struct Setting {
  std::string kind;
  std::map<std::string, double> values;
  double Get(const std::string& key, double fallback) const {
    auto it = values.find(key);
    return it == values.end() ? fallback : it->second;
  }
};

bool ParseSetting(const std::string& text, Setting* out) {
  const std::size_t colon = text.find(':');
  out->kind = text.substr(0, colon);
  if (out->kind != "adaptive" && out->kind != "mba" && out->kind != "curve") return false;
  if (colon == std::string::npos) return true;
  std::stringstream ss(text.substr(colon + 1));
  std::string item;
  while (std::getline(ss, item, ',')) {
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos) return false;
    out->values[item.substr(0, eq)] = std::atof(item.substr(eq + 1).c_str());
  }
  return true;
}

struct Scene {
  const FittedSurface* fitted = nullptr;
  std::vector<Vec3> fit_points, holdout_points;
  std::vector<PointFit> holdout_fits;
  double scale = 1.0;
  std::int64_t points = 0;
  int threads = 2;
  bool tess = true;
  bool quantiles = false;
};

struct Row {
  double e1 = 0, holdout = 0, tess = -1, seconds = 0, cpu = 0;
  std::vector<double> holdout_all;
  std::int64_t coefficients = 0;
  int levels = 0;
};

Row Measure(const Scene& sc, const BsplineDisplacement& disp) {
  const ManifoldDomain& domain = *sc.fitted->surface.domain;
  const LocalPatch* patches = sc.fitted->surface.patches.data();
  Row row;
  double sum = 0.0, n = 0.0;
  for (std::size_t i = 0; i < sc.fit_points.size(); ++i) {
    const PointFit& f = sc.fitted->point_fits[i];
    if (f.status == PointFitStatus::kOutside) continue;
    SurfacePoint sp;
    EvaluateSurface(domain, patches, &disp, f.face, f.uv, &sp);
    sum += glm::length(sp.position - sc.fit_points[i]), n += 1.0;
  }
  row.e1 = sum / n / sc.scale;
  sum = 0.0, n = 0.0;
  std::vector<double> hd;
  for (std::size_t i = 0; i < sc.holdout_points.size(); ++i) {
    const PointFit& f = sc.holdout_fits[i];
    if (f.status == PointFitStatus::kOutside) continue;
    Index face = f.face;
    Vec2 uv = f.uv;
    const double dist =
        ClosestPointOnSurface(domain, patches, &disp, sc.holdout_points[i], &face, &uv);
    sum += dist;
    n += 1.0;
    hd.push_back(dist / sc.scale);
  }
  row.holdout = sum / n / sc.scale;
  row.holdout_all = hd;
  if (sc.tess) {
    TessellationPattern pattern;
    TessellationPattern::Build(domain.topology(), 16, &pattern);
    std::vector<Vec3> x(pattern.samples.size());
    EvaluateSamples(domain, patches, &disp, pattern.samples.data(), x.size(), x.data(), nullptr);
    TriangleDistanceTree tree;
    tree.Build(x, pattern.triangles);
    double s = 0.0;
    for (const Vec3& p : sc.fit_points) s += tree.Query(p).distance;
    row.tess = s / static_cast<double>(sc.fit_points.size()) / sc.scale;
  }
  row.coefficients = disp.num_coefficients();
  row.levels = disp.max_levels();
  return row;
}

void Print(const Scene& sc, const std::string& name, const Row& r) {
  std::printf(
      "%-58s E1 %.3e  held-out %.3e (%.2f x E1)  tess16 %s  coeff %8lld (%.2f/pt)  "
      "levels %d  %.3f s (cpu %.3f s)\n",
      name.c_str(), r.e1, r.holdout, r.holdout / r.e1,
      r.tess < 0 ? "   -     "
                 : (std::to_string(r.tess).substr(0, 9) + (r.tess <= r.e1 ? "<" : ">")).c_str(),
      static_cast<long long>(r.coefficients),
      static_cast<double>(r.coefficients) / static_cast<double>(sc.points), r.levels, r.seconds,
      r.cpu);
  if (sc.quantiles && !r.holdout_all.empty()) {
    std::vector<double> v = r.holdout_all;
    std::sort(v.begin(), v.end());
    auto q = [&](double f) {
      return v[static_cast<std::size_t>(f * static_cast<double>(v.size() - 1))];
    };
    std::printf(
        "    held-out quantiles: 25%% %.3g, 50%% %.3g, 75%% %.3g, 90%% %.3g, 99%% %.3g, max %.3g\n",
        q(0.25), q(0.5), q(0.75), q(0.9), q(0.99), v.back());
  }
  std::fflush(stdout);
}

// A model-free estimate of how well any smooth surface can predict a held-out point: fit a
// polynomial height field (degree 1..3, in the principal frame of the point's K nearest fitted
// points) to those neighbours and measure the held-out point's height above it. Prints the
// mean over the held-out points, in the fit's unit, for each K and degree.
void PrintLocalFloor(const Scene& sc) {
  const std::vector<int> ks = {8, 12, 16, 24, 32, 48, 64};
  std::printf(
      "local polynomial prediction of the held-out points (mean |height error|, unit as E1):\n");
  std::printf("%6s %10s %10s %10s\n", "K", "plane", "quadric", "cubic");
  std::vector<std::vector<double>> sum(ks.size(), std::vector<double>(3, 0.0));
  std::vector<std::pair<double, std::size_t>> d(sc.fit_points.size());
  std::vector<double> quadric12;
  for (const Vec3& p : sc.holdout_points) {
    for (std::size_t i = 0; i < sc.fit_points.size(); ++i) {
      const Vec3 e = sc.fit_points[i] - p;
      d[i] = {glm::dot(e, e), i};
    }
    std::partial_sort(d.begin(), d.begin() + ks.back(), d.end());
    for (std::size_t ki = 0; ki < ks.size(); ++ki) {
      const int k = ks[ki];
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int a = 0; a < k; ++a) {
        const Vec3& q = sc.fit_points[d[static_cast<std::size_t>(a)].second];
        c += Eigen::Vector3d(q.x, q.y, q.z);
      }
      c /= k;
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      for (int a = 0; a < k; ++a) {
        const Vec3& q = sc.fit_points[d[static_cast<std::size_t>(a)].second];
        const Eigen::Vector3d x = Eigen::Vector3d(q.x, q.y, q.z) - c;
        cov += x * x.transpose();
      }
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
      const Eigen::Vector3d n = es.eigenvectors().col(0), u = es.eigenvectors().col(2),
                            v = es.eigenvectors().col(1);
      const Eigen::Vector3d pp = Eigen::Vector3d(p.x, p.y, p.z) - c;
      for (int degree = 1; degree <= 3; ++degree) {
        const int terms = degree == 1 ? 3 : degree == 2 ? 6 : 10;
        if (k < terms + 2) {
          sum[ki][static_cast<std::size_t>(degree - 1)] = -1e300;
          continue;
        }
        auto row = [&](double x, double y, double* r) {
          int t = 0;
          for (int e = 0; e <= degree; ++e) {
            for (int a = 0; a <= e; ++a) r[t++] = std::pow(x, e - a) * std::pow(y, a);
          }
        };
        Eigen::MatrixXd m(k, terms);
        Eigen::VectorXd h(k);
        const double scale = std::sqrt(d[static_cast<std::size_t>(k - 1)].first);
        for (int a = 0; a < k; ++a) {
          const Vec3& q = sc.fit_points[d[static_cast<std::size_t>(a)].second];
          const Eigen::Vector3d x = Eigen::Vector3d(q.x, q.y, q.z) - c;
          double r[10];
          row(x.dot(u) / scale, x.dot(v) / scale, r);
          for (int t = 0; t < terms; ++t) m(a, t) = r[t];
          h(a) = x.dot(n);
        }
        const Eigen::VectorXd coef = m.colPivHouseholderQr().solve(h);
        double r[10];
        row(pp.dot(u) / scale, pp.dot(v) / scale, r);
        double pred = 0.0;
        for (int t = 0; t < terms; ++t) pred += coef(t) * r[t];
        sum[ki][static_cast<std::size_t>(degree - 1)] += std::abs(pp.dot(n) - pred);
        if (k == 12 && degree == 2) quadric12.push_back(std::abs(pp.dot(n) - pred) / sc.scale);
      }
    }
  }
  std::sort(quadric12.begin(), quadric12.end());
  auto q = [&](double f) {
    return quadric12[static_cast<std::size_t>(f * static_cast<double>(quadric12.size() - 1))];
  };
  std::printf(
      "K = 12 quadric quantiles: 25%% %.3g, 50%% %.3g, 75%% %.3g, 90%% %.3g, 99%% %.3g, max %.3g\n",
      q(0.25), q(0.5), q(0.75), q(0.9), q(0.99), quadric12.back());
  const double n = static_cast<double>(sc.holdout_points.size());
  for (std::size_t ki = 0; ki < ks.size(); ++ki) {
    std::printf("%6d", ks[ki]);
    for (int dg = 0; dg < 3; ++dg) {
      const double v = sum[ki][static_cast<std::size_t>(dg)];
      if (v < 0) {
        std::printf(" %10s", "-");
      } else {
        std::printf(" %10.3e", v / n / sc.scale);
      }
    }
    std::printf("\n");
  }
}

double Seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  std::string path = "../shared/data/scans/stanford-bunny.obj", control_path;
  int control_vertices = 540, threads = 2;
  bool tess = true, floor = false;
  std::vector<Setting> settings;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--control-vertices" && i + 1 < argc) {
      control_vertices = std::atoi(argv[++i]);
    } else if (a == "--control-mesh" && i + 1 < argc) {
      control_path = argv[++i];
    } else if (a == "--threads" && i + 1 < argc) {
      threads = std::atoi(argv[++i]);
    } else if (a == "--no-tess") {
      tess = false;
    } else if (a == "--floor") {
      floor = true;
    } else if (a.find(':') != std::string::npos || a == "adaptive" || a == "mba") {
      Setting s;
      if (!ParseSetting(a, &s)) {
        std::fprintf(stderr, "bench_displacement: bad setting %s\n", a.c_str());
        return 2;
      }
      settings.push_back(s);
    } else {
      path = a;
    }
  }
  if (!std::filesystem::exists(path)) {
    std::printf("bench_displacement: skipped: %s not found (run from the repo root)\n",
                path.c_str());
    return 0;
  }
  if (settings.empty()) settings.push_back(Setting{"adaptive", {}});
  PolygonMesh mesh, control;
  Index dropped = 0;
  Status s = ReadFitInput(path, &mesh, &dropped);
  if (s.ok() && !control_path.empty()) s = ReadObj(control_path, &control);
  if (!s.ok()) {
    std::fprintf(stderr, "bench_displacement: %s\n", s.message().c_str());
    return 1;
  }
  FitInput input;
  input.points = mesh.positions;
  input.mesh = &mesh;
  if (!control_path.empty()) input.control = &control;
  FitOptions options;
  options.control_vertices = control_vertices;
  options.threads = threads;
  FittedSurface fitted;
  FitReport report;
  s = FitSurface(input, options, &fitted, &report);
  if (!s.ok()) {
    std::fprintf(stderr, "bench_displacement: %s\n", s.message().c_str());
    return 1;
  }
  Scene sc;
  sc.fitted = &fitted;
  sc.scale = report.scale;
  sc.points = report.points;
  sc.threads = threads;
  sc.tess = tess;
  sc.quantiles = floor;
  for (std::size_t i = 0; i < input.points.size(); ++i) {
    (IsHeldOut(i, options.holdout, options.holdout_seed) ? sc.holdout_points : sc.fit_points)
        .push_back(input.points[i]);
  }
  PointFitOptions pf;
  pf.threads = threads;
  pf.tolerance = 1e-9 * report.scale;
  FitPoints(fitted.surface, sc.holdout_points, pf, &sc.holdout_fits);
  const ManifoldDomain& domain = *fitted.surface.domain;
  if (floor) PrintLocalFloor(sc);
  std::printf("%s: %lld points, %lld control vertices, %d threads\n", path.c_str(),
              static_cast<long long>(report.points),
              static_cast<long long>(report.control_vertices), threads);
  {
    ZeroDisplacement zero;
    Row r;
    // The domain surface (no displacement) for reference.
    BsplineDisplacementData empty;
    empty.half_extent.assign(static_cast<std::size_t>(domain.num_vertices()), 1.0);
    empty.num_levels.assign(static_cast<std::size_t>(domain.num_vertices()), 0);
    empty.offsets.assign(static_cast<std::size_t>(domain.num_vertices()) + 1, 0);
    Status st;
    auto d = BsplineDisplacement::Create(empty, domain.num_vertices(), &st);
    r = Measure(sc, *d);
    Print(sc, "domain surface", r);
  }
  std::vector<double> half(static_cast<std::size_t>(domain.num_vertices()));
  for (Index v = 0; v < domain.num_vertices(); ++v) {
    half[static_cast<std::size_t>(v)] = ChartHalfExtent(domain.chart(v), domain.options().blend_lb);
  }
  std::vector<DisplacementTarget> targets;
  MakeDisplacementTargets(domain, fitted.surface.patches.data(), fitted.point_fits, &targets);
  for (const Setting& st : settings) {
    std::string name = st.kind;
    for (const auto& kv : st.values) {
      char buf[64];
      std::snprintf(buf, sizeof buf, " %s=%g", kv.first.c_str(), kv.second);
      name += buf;
    }
    if (st.kind == "mba") {
      DisplacementFitOptions o;
      o.method = DisplacementMethod::kMba;
      o.density = st.Get("density", o.density);
      o.finest_passes = static_cast<int>(st.Get("passes", o.finest_passes));
      o.smoothing = st.Get("smoothing", o.smoothing);
      o.max_levels = static_cast<int>(st.Get("levels", o.max_levels));
      o.threads = threads;
      std::vector<ChartSample> samples;
      for (const PointFit& f : fitted.point_fits) {
        if (f.status == PointFitStatus::kOptimized) {
          samples.insert(samples.end(), f.optimized, f.optimized + f.num_optimized);
        }
      }
      const auto t0 = std::chrono::steady_clock::now();
      BsplineDisplacementData data = FitDisplacements(domain, samples, o);
      const double sec = Seconds(t0);
      Status cs;
      auto d = BsplineDisplacement::Create(std::move(data), domain.num_vertices(), &cs);
      Row r = Measure(sc, *d);
      r.seconds = sec;
      Print(sc, name, r);
      continue;
    }
    AdaptiveDisplacementOptions o;
    o.min_node_weight = st.Get("weight", o.min_node_weight);
    o.residual_threshold = st.Get("residual", o.residual_threshold);
    o.max_coefficients_per_point = st.Get("budget", o.max_coefficients_per_point);
    o.smoothing = st.Get("smoothing", o.smoothing);
    o.validation = st.Get("validation", o.validation);
    o.min_improvement = st.Get("improvement", o.min_improvement);
    o.solver_iterations = static_cast<int>(st.Get("iterations", o.solver_iterations));
    o.solver_tolerance = st.Get("tolerance", o.solver_tolerance);
    o.consistency = st.Get("consistency", o.consistency);
    o.max_levels = static_cast<int>(st.Get("levels", o.max_levels));
    o.threads = threads;
    std::vector<int> level_counts;
    if (st.kind == "curve") {
      o.validation = 0.0;
      for (int l = 1; l <= o.max_levels; ++l) level_counts.push_back(l);
    } else {
      level_counts.push_back(o.max_levels);
    }
    for (int l : level_counts) {
      AdaptiveDisplacementOptions ol = o;
      ol.max_levels = l;
      BsplineDisplacementData data;
      AdaptiveDisplacementReport rep;
      const auto t0 = std::chrono::steady_clock::now();
      const std::clock_t c0 = std::clock();
      Status fs = FitAdaptiveDisplacement(half, targets, ol, &data, &rep);
      const double sec = Seconds(t0);
      const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
      if (!fs.ok()) {
        std::fprintf(stderr, "bench_displacement: %s\n", fs.message().c_str());
        return 1;
      }
      Status cs;
      auto d = BsplineDisplacement::Create(std::move(data), domain.num_vertices(), &cs);
      if (!d) {
        std::fprintf(stderr, "bench_displacement: %s\n", cs.message().c_str());
        return 1;
      }
      Row r = Measure(sc, *d);
      r.seconds = sec;
      r.cpu = cpu;
      Print(sc, st.kind == "curve" ? name + " L=" + std::to_string(l) : name, r);
      if (st.kind != "curve") {
        for (const AdaptiveLevelReport& lr : rep.trial) {
          std::printf("    trial level %d: %7lld nodes, train %.3e, validation %.3e, %d steps\n",
                      lr.level, static_cast<long long>(lr.nodes), lr.train_mean / sc.scale,
                      lr.validation_mean / sc.scale, lr.iterations);
        }
        std::printf("    kept %d levels (stopped by %s), nodes per level:", rep.levels,
                    rep.stopped_by.c_str());
        for (std::int64_t n : rep.level_nodes) std::printf(" %lld", static_cast<long long>(n));
        std::printf("\n");
      }
    }
  }
  return 0;
}

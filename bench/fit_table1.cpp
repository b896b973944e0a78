// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The fitting benchmark (docs/results.md, docs/fitting.md, docs/characters.md), three rows:
//  - bunny: paper Table 1 side by side with ours: fits ../shared/data/scans/stanford-bunny.obj
//    with 540 control vertices, reports the fit's own errors and timings and the control mesh's
//    quality, checks them independently against the level-16 tessellation (point-to-triangle
//    distances), and checks that --threads 1 and 2 give the same .dsurf bytes;
//  - torus: the built-in torus tessellated at level 12 (6,912 points) fitted with 200 control
//    vertices; the domain surface (no displacement) and the full surface against the input,
//    both directions;
//  - characters: RiggedSimple, RiggedFigure, Fox and CesiumMan fitted as `dermis fit` does,
//    posed at rest in `lod` mode at level 8 (as `dermis animate --clip rest --mode lod --level
//    8`) and compared with the source posed at rest, two-sided Hausdorff in % of the diagonal;
//    the lod normals against the source's shading normals; and the integral of |H| over the
//    lod surface against the source's (ripples and lumps raise it; docs/characters.md).
// Usage (from the repo root): bench_fit [OBJ|PLY] [--rows bunny,torus,characters]
//                             [--rows characters:NAME,NAME] (only those characters)
//                             [--crease-rows 0|1] [--displacement-levels L] (characters' lod)
//                             [--control-vertices N] [--torus-vertices N] [--torus-draws N]
//                             [--control-method remesh|simplify]
//                             [--density D] [--control-fit ITERATIONS] [--tangent-weight T]
//                             [--tangent-damping D] [--patch-agreement W] [--robust-cutoff C]
//                             [--noisy-ratio R] (0: the control fit always fully regularised)
//                             [--chart-type characteristic|complex|isodistance] [--finest-passes P]
//                             [--loop-segments N] (coarse edges per boundary loop, at least)
//                             [--no-cover-boundary] (FitOptions::cover_boundary off)
//                             [--smoothing S] [--samples S] [--crease-samples C] [--crease-angle A]
//                             [--low-poly-crease-angle A]
//                             [--max-turn T] [--repeat R] [--where] [--node-weight W]
//                             [--budget COEFFICIENTS_PER_POINT]
//                             [--level-smoothing S] (the levels' smoothing; characters' parts
//                             on a control mesh without creases)
//                             [--crease-smoothing S] (characters' parts on a crease-kept mesh)
//                             [--shading-shape A] (characters' shading surface, 0: flat)
//                             [--shading-max-move M] (its largest move, of the diagonal)
//                             [--vertex-weight W] (characters' vertices against one sample)
//                             [--creases-ignore-shading] (smooth-shaded sharp edges are creases)
//                             [--no-check-shading] (the check points' distance rule alone)
//                             [--input-quads R] (characters: the input's own quads; 0: off)
//                             [--crease-support K] (support rows beside closed crease loops; 1:
//                             off) [--creases-closed] (no cut along hard creases)
//                             [--detail] [--mba]
// --density, --finest-passes and --smoothing set the paper's per-chart MBA (--mba); the default
// displacement fit is the adaptive one (docs/fitting.md, "Adaptive displacement levels").
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "dermis/asset/asset_pose.h"
#include "dermis/dsurf/dsurf.h"
#include "dermis/offline/build/control_mesh.h"
#include "dermis/offline/build/domain_builder.h"
#include "dermis/offline/character/character_fit.h"
#include "dermis/offline/character/character_pose.h"
#include "dermis/offline/character/skin_transfer.h"
#include "dermis/offline/fit/surface_fit.h"
#include "dermis/offline/fit/surface_projection.h"
#include "dermis/offline/geometry/builtin_meshes.h"
#include "dermis/offline/geometry/mesh_metrics.h"
#include "dermis/offline/geometry/triangle_distance.h"
#include "dermis/offline/io/point_input.h"
#include "dermis/plugins/gltf.h"
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

// Settings shared by the rows.
struct Settings {
  std::string bunny = "../shared/data/scans/stanford-bunny.obj";
  std::string rows = "bunny,torus,characters";
  int control_vertices = 540, torus_vertices = 200, repeat = 3;
  int torus_draws = 8;  ///< --torus-draws: torus inputs moved by 1e-12 (0: only the exact one).
  bool detail = false, mba = false;
  bool where = false;             ///< --where: the largest character distances and what is there.
  bool no_crease_remesh = false;  ///< --no-crease-remesh: the remesh ignores creases.
  bool creases_ignore_shading = false;  ///< --creases-ignore-shading: smooth-shaded creases too.
  bool no_check_shading = false;        ///< --no-check-shading: the check points' distances only.
  double crease_support = -1.0;         ///< --crease-support K; -1: CharacterFitOptions' default
  bool creases_closed = false;          ///< --creases-closed: no cut along hard creases
  double input_quads = -1.0;            ///< --input-quads R; -1: CharacterFitOptions' default
  int compare_without_creases = -1;     ///< --compare-without-creases 0|1 (-1: the default).
  int compare_simplified = -1;          ///< --compare-simplified 0|1 (-1: the default).
  ControlMeshMethod method = ControlMeshMethod::kRemesh;
  double density = -1.0;           // -1: FitOptions' default
  int control_fit = -1;            // -1: FitOptions' default
  double tangent_weight = -1.0;    // -1: ControlFitOptions' default
  double tangent_damping = -1.0;   // -1: ControlFitOptions' default
  double patch_agreement = -1.0;   // -1: FitOptions' default
  double noisy_ratio = -1.0;       // --noisy-ratio R: FitOptions::control_fit_noisy_ratio
  bool no_cover_boundary = false;  // FitOptions::cover_boundary off
  double robust_cutoff = -1.0;     // -1: ControlFitOptions' default (0: no robust weights)
  int chart_type = -1;             // -1: DomainOptions' default; else a ChartType value
  int loop_segments = -1;          // -1: SizingOptions' default (edges per boundary loop, at least)
  int finest_passes = -1;          // -1: FitOptions' default
  double smoothing = -1.0;         // -1: FitOptions' default
  double samples = -1.0;           // -1: CharacterFitOptions' default
  double crease_samples = -1.0;    // -1: CharacterFitOptions' default
  int crease_rows = -1;            // -1: CharacterFitOptions' default
  int displacement_levels = -1;    // characters: displacement levels of the lod surface (-1: all)
  double crease_angle = -1.0;      // -1: CharacterFitOptions' default
  double low_poly_crease_angle = -1.0;  // -1: CharacterFitOptions' default
  double node_weight = -1.0;            // -1: the fit's default
  double budget = -1.0;                 // coefficients per point; -1: the fit's default, 0: none
  double max_turn = -1.0;               // -1: CharacterFitOptions' default
  double level_smoothing = -1.0;        // -1: the adaptive fit's default
  double crease_smoothing = -1.0;       // -1: CharacterFitOptions' default
  double shading_shape = -1.0;          // -1: CharacterFitOptions' default
  double shading_max_move = -1.0;       // -1: CharacterFitOptions' default
  double vertex_weight = -1.0;          // -1: CharacterFitOptions' default
  bool Row(const char* name) const { return rows.find(name) != std::string::npos; }
};

void ApplySettings(const Settings& st, FitOptions* options) {
  options->control_method = st.method;
  if (st.density >= 0.0) options->displacement.density = st.density;
  if (st.control_fit >= 0) options->control_fit_iterations = st.control_fit;
  if (st.tangent_weight >= 0.0) options->control_fit.tangent_weight = st.tangent_weight;
  if (st.tangent_damping >= 0.0) options->control_fit.tangent_damping = st.tangent_damping;
  if (st.patch_agreement >= 0.0) options->control_fit.patch_agreement = st.patch_agreement;
  if (st.noisy_ratio >= 0.0) options->control_fit_noisy_ratio = st.noisy_ratio;
  if (st.no_cover_boundary) options->cover_boundary = false;
  if (st.robust_cutoff >= 0.0) options->control_fit.robust_cutoff = st.robust_cutoff;
  if (st.chart_type >= 0) options->domain.chart_type = static_cast<ChartType>(st.chart_type);
  if (st.loop_segments >= 0) options->remesh.sizing.loop_segments = st.loop_segments;
  if (st.finest_passes >= 1) options->displacement.finest_passes = st.finest_passes;
  if (st.smoothing >= 0.0) options->displacement.smoothing = st.smoothing;
  if (st.mba) options->displacement.method = DisplacementMethod::kMba;
  if (st.level_smoothing >= 0.0) options->displacement.adaptive.smoothing = st.level_smoothing;
  if (st.node_weight >= 0.0) options->displacement.adaptive.min_node_weight = st.node_weight;
  if (st.budget >= 0.0) options->displacement.adaptive.max_coefficients_per_point = st.budget;
}

void PrintControlMesh(const char* name, const FitReport& r) {
  const ControlMeshInfo& c = r.control_mesh;
  const QuadRemeshReport& q = c.quality;
  std::printf(
      "control mesh (%s): method %s%s%s, %d vertices for a target of %d (%+.1f%%), %d quads; "
      "interior valence 4: %.1f%% (%d of %d), max valence %d; corner angles %.1f..%.1f deg, "
      "%.1f%% within 60..120; %d components, %d boundary loops; %.3f s incl. control-vertex fit\n",
      name, c.method.c_str(), c.fallback.empty() ? "" : " (fallback: ",
      c.fallback.empty() ? "" : (c.fallback + ")").c_str(), q.vertices, q.target_vertices,
      100.0 * (q.vertices - q.target_vertices) / std::max(q.target_vertices, 1), q.faces,
      100.0 * q.valence4_share, q.interior_valence4, q.interior_vertices, q.max_valence,
      q.min_corner_angle_deg, q.max_corner_angle_deg, 100.0 * q.corners_60_120_share, q.components,
      q.boundary_loops, r.seconds.control_mesh);
  if (c.method == "remesh") {
    std::printf(
        "control mesh (%s): seed %d vertices -> isotropic %d vertices -> %d quads + %d "
        "triangles -> split%s\n",
        name, q.seed_vertices, q.triangle_vertices, q.quads_paired, q.triangles_unpaired,
        q.input_quads ? " (replaced by the input's own quads)" : "");
  }
  std::printf(
      "control-vertex fit (%s): %lld rounds, data noise %.3g of the spacing -> regularisation "
      "%.2f\n",
      name, static_cast<long long>(r.control_fit_rounds), r.noise_ratio,
      r.control_fit_regularisation);
}

// Mean and largest distance from each point to a triangle mesh.
void MeanMax(const std::vector<Vec3>& points, const TriangleDistanceTree& tree, double scale,
             double* mean, double* max) {
  double sum = 0.0, mx = 0.0;
  for (const Vec3& p : points) {
    const double d = tree.Query(p).distance / scale;
    sum += d, mx = std::max(mx, d);
  }
  *mean = sum / static_cast<double>(std::max<std::size_t>(points.size(), 1));
  *max = mx;
}

// The domain surface (no displacement) and the full surface, tessellated at `level`, against
// the input mesh in both directions: every input vertex to the surface's triangles and every
// surface vertex to the input's triangles (mean / max, in the unit where the largest side is 1).
// Distances of one surface (domain or full), in the unit where the largest side is 1.
struct SurfaceDistances {
  double to_surface_mean = 0, to_surface_max = 0;  // data -> surface
  double to_data_mean = 0, to_data_max = 0;        // surface -> data
};

// Prints the domain and the full surface's distances (row 0 and 1 of *out if not null).
void PrintSurfaceDistances(const char* name, const FittedSurface& fitted, const PolygonMesh& mesh,
                           double scale, int level, SurfaceDistances* out = nullptr,
                           bool print = true) {
  TriangleDistanceTree data_tree;
  data_tree.Build(mesh.positions, TriangulateFan(mesh));
  TessellationPattern fine;
  TessellationPattern::Build(fitted.surface.domain->topology(), level, &fine);
  if (print) {
    std::printf("| %s | data -> surface mean / max | surface -> data mean / max | max |\n", name);
    std::printf("|---|---|---|---|\n");
  }
  for (int full = 0; full < 2; ++full) {
    std::unique_ptr<TruncatedDisplacement> none;
    if (!full) none = std::make_unique<TruncatedDisplacement>(fitted.displacement.get(), 0);
    const Displacement* disp =
        full ? static_cast<const Displacement*>(fitted.displacement.get()) : none.get();
    std::vector<Vec3> x(fine.samples.size());
    EvaluateSamples(*fitted.surface.domain, fitted.surface.patches.data(), disp,
                    fine.samples.data(), x.size(), x.data(), nullptr);
    TriangleDistanceTree surface_tree;
    surface_tree.Build(x, fine.triangles);
    double m1 = 0, x1 = 0, m2 = 0, x2 = 0;
    MeanMax(mesh.positions, surface_tree, scale, &m1, &x1);
    MeanMax(x, data_tree, scale, &m2, &x2);
    if (out) out[full] = SurfaceDistances{m1, x1, m2, x2};
    if (!print) continue;
    std::printf("| %s | %.3g / %.3g | %.3g / %.3g | %.3g |\n",
                full ? "full surface" : "domain surface (0 displacement levels)", m1, x1, m2, x2,
                std::max(x1, x2));
  }
}

int RunBunny(const Settings& st) {
  const std::string& path = st.bunny;
  if (!std::filesystem::exists(path)) {
    std::printf(
        "bench_fit: bunny skipped: %s not found (run from the repo root with ../shared/data)\n",
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
  options.control_vertices = st.control_vertices;
  ApplySettings(st, &options);
  std::vector<double> totals, control;
  FitReport report;
  FittedSurface fitted;
  std::string bytes_default;
  for (int r = 0; r < st.repeat; ++r) {
    s = FitSurface(input, options, &fitted, &report);
    if (!s.ok()) {
      std::fprintf(stderr, "bench_fit: %s\n", s.message().c_str());
      return 1;
    }
    totals.push_back(report.seconds.total);
    control.push_back(report.seconds.control_mesh);
  }
  std::sort(totals.begin(), totals.end());
  std::sort(control.begin(), control.end());
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
  if (st.detail) PrintDetail(fitted, mesh, fit_points, tess, report.scale);
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
              path.c_str(), report.threads, st.repeat);
  std::printf("| | paper | dermis |\n|---|---|---|\n");
  std::printf("| data points | 34,834 | %lld (%lld fitted, %lld held out, %lld outside) |\n",
              static_cast<long long>(report.points), static_cast<long long>(report.points_fitted),
              static_cast<long long>(report.points_holdout),
              static_cast<long long>(report.points_outside));
  std::printf("| control vertices | 540 | %lld (%lld quads) |\n",
              static_cast<long long>(report.control_vertices),
              static_cast<long long>(report.control_faces));
  std::printf("| control mesh (s) | (commercial tool) | %.3f (min %.3f, max %.3f) |\n",
              control[control.size() / 2], control.front(), control.back());
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
  std::printf(
      "surfaces tessellated at level 16 against the scan's triangles (every vertex, held-out "
      "ones too):\n");
  PrintSurfaceDistances("bunny", fitted, mesh, report.scale, 16);
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
  PrintControlMesh("bunny", report);
  std::printf(
      "boundary cover (bunny): %lld scan boundary vertices beyond the domain surface's boundary "
      "curve (farthest %.3g), %lld boundary control vertices moved out\n",
      static_cast<long long>(report.boundary_points_beyond), report.boundary_largest_excess,
      static_cast<long long>(report.boundary_vertices_moved));
  // The control mesh build alone in CPU seconds (it runs on one thread, so this is its wall
  // time on an idle core; the wall times above grow with the machine's load).
  std::vector<double> cpu;
  for (int r = 0; r < st.repeat; ++r) {
    ControlMeshOptions cm;
    cm.target_vertices = options.control_vertices;
    cm.method = options.control_method;
    PolygonMesh built;
    const std::clock_t c0 = std::clock();
    if (!BuildControlMesh(mesh, cm, &built).ok()) return 1;
    cpu.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
  }
  std::sort(cpu.begin(), cpu.end());
  std::printf("control mesh build alone: %.3f s CPU (median of %d; min %.3f, max %.3f)\n",
              cpu[cpu.size() / 2], st.repeat, cpu.front(), cpu.back());
  return 0;
}

// One torus fit: the input moved by uniform noise of at most `jitter` model units per
// coordinate (seeded by `seed`; 0: none), fitted and measured; prints its tables if `print`.
int FitTorus(const Settings& st, double jitter, unsigned seed, bool print, SurfaceDistances out[2],
             FitReport* report) {
  // The input: the built-in torus's manifold surface tessellated at level 12 (as `dermis
  // tessellate --builtin torus --level 12`).
  PolygonMesh control;
  Status s = MakeBuiltinMesh("torus", &control);
  ControlSurface cs;
  if (s.ok()) s = BuildControlSurface(control, DomainOptions(), &cs);
  TessellationPattern pattern;
  if (s.ok()) s = TessellationPattern::Build(cs.domain->topology(), 12, &pattern);
  if (!s.ok()) {
    std::fprintf(stderr, "bench_fit: torus: %s\n", s.message().c_str());
    return 1;
  }
  PolygonMesh mesh;
  mesh.source_name = "torus (level 12)";
  mesh.positions.resize(pattern.samples.size());
  EvaluateSamples(*cs.domain, cs.patches.data(), nullptr, pattern.samples.data(),
                  pattern.samples.size(), mesh.positions.data(), nullptr);
  if (jitter > 0.0) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-jitter, jitter);
    for (Vec3& p : mesh.positions) {
      const double dx = u(rng), dy = u(rng), dz = u(rng);
      p += Vec3(dx, dy, dz);
    }
  }
  for (std::size_t t = 0; t < pattern.triangles.size(); t += 3) {
    mesh.AddFace({static_cast<Index>(pattern.triangles[t]),
                  static_cast<Index>(pattern.triangles[t + 1]),
                  static_cast<Index>(pattern.triangles[t + 2])});
  }
  FitInput input;
  input.points = mesh.positions;
  input.mesh = &mesh;
  FitOptions options;
  options.control_vertices = st.torus_vertices;
  ApplySettings(st, &options);
  FittedSurface fitted;
  s = FitSurface(input, options, &fitted, report);
  if (!s.ok()) {
    std::fprintf(stderr, "bench_fit: torus: %s\n", s.message().c_str());
    return 1;
  }
  if (print) {
    std::printf(
        "torus: %zu points, %lld control vertices (%lld quads), unit: largest side 1 (%.4g "
        "model units); surface tessellated at level 24\n",
        mesh.positions.size(), static_cast<long long>(report->control_vertices),
        static_cast<long long>(report->control_faces), report->scale);
  }
  PrintSurfaceDistances("torus", fitted, mesh, report->scale, 24, out, print);
  if (print) PrintControlMesh("torus", *report);
  return 0;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0.0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

int RunTorus(const Settings& st) {
  SurfaceDistances first[2];
  FitReport report;
  if (FitTorus(st, 0.0, 0, true, first, &report) != 0) return 1;
  if (st.torus_draws <= 0) return 0;
  // The input is exactly symmetric, so the control mesh's simplification and remesh break ties
  // by rounding: inputs moved by 1e-12 of the model (far below any real data's noise) give
  // different control meshes. The spread over such draws says how much one row means.
  std::printf(
      "torus, %d more draws (input moved by at most 1e-12 model units, seeds 1..%d): domain "
      "surface, mean / max of both directions, interior valence 4\n",
      st.torus_draws, st.torus_draws);
  std::printf("| draw | control vertices | valence 4 | domain mean | domain max | full max |\n");
  std::printf("|---|---|---|---|---|---|\n");
  std::vector<double> means, maxes, full_maxes;
  for (int d = 0; d <= st.torus_draws; ++d) {
    SurfaceDistances dist[2];
    if (d == 0) {
      dist[0] = first[0], dist[1] = first[1];
    } else if (FitTorus(st, 1e-12, static_cast<unsigned>(d), false, dist, &report) != 0) {
      return 1;
    }
    const double mean = std::max(dist[0].to_surface_mean, dist[0].to_data_mean);
    const double mx = std::max(dist[0].to_surface_max, dist[0].to_data_max);
    const double full = std::max(dist[1].to_surface_max, dist[1].to_data_max);
    means.push_back(mean), maxes.push_back(mx), full_maxes.push_back(full);
    std::printf("| %d | %lld | %.1f%% | %.3g | %.3g | %.3g |\n", d,
                static_cast<long long>(report.control_vertices),
                100.0 * report.control_mesh.quality.valence4_share, mean, mx, full);
  }
  std::printf(
      "| median (min..max) | | | %.3g (%.3g..%.3g) | %.3g (%.3g..%.3g) | %.3g (%.3g..%.3g) |\n",
      Median(means), *std::min_element(means.begin(), means.end()),
      *std::max_element(means.begin(), means.end()), Median(maxes),
      *std::min_element(maxes.begin(), maxes.end()), *std::max_element(maxes.begin(), maxes.end()),
      Median(full_maxes), *std::min_element(full_maxes.begin(), full_maxes.end()),
      *std::max_element(full_maxes.begin(), full_maxes.end()));
  return 0;
}

struct Triangles {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;  // unit, one per position (shading normals), or empty
  std::vector<std::uint32_t> indices;
  void Append(const std::vector<Vec3>& x, const std::vector<std::uint32_t>& tris,
              const std::vector<Vec3>& n = {}) {
    const std::uint32_t base = static_cast<std::uint32_t>(positions.size());
    positions.insert(positions.end(), x.begin(), x.end());
    if (n.size() == x.size()) normals.insert(normals.end(), n.begin(), n.end());
    for (std::uint32_t i : tris) indices.push_back(base + i);
  }
};

// How far the lod surface's normals turn from the source's shading normals (its NORMAL
// attribute, interpolated across the closest source triangle): the mean and the 95th
// percentile over the lod surface's area, degrees (each lod vertex stands for a third of its
// triangles' area, so a tessellation denser in one place, as beside a crease's support row,
// does not weigh that place more). Ripples and lumps too small for the Hausdorff distance show
// here (and in the shading). Vertices whose closest source point is further than `near` are
// left out (they measure the distance, not the shading). -1 without normals.
void ShadingDeviation(const Triangles& lod, const Triangles& source,
                      const TriangleDistanceTree& tree, double near, double* mean, double* p95) {
  *mean = *p95 = -1.0;
  if (lod.normals.size() != lod.positions.size() ||
      source.normals.size() != source.positions.size())
    return;
  std::vector<double> area(lod.positions.size(), 0.0);
  for (std::size_t t = 0; t + 2 < lod.indices.size(); t += 3) {
    const Vec3& a = lod.positions[lod.indices[t]];
    const double third = glm::length(glm::cross(lod.positions[lod.indices[t + 1]] - a,
                                                lod.positions[lod.indices[t + 2]] - a)) /
                         6.0;
    for (int k = 0; k < 3; ++k) area[lod.indices[t + static_cast<std::size_t>(k)]] += third;
  }
  std::vector<std::pair<double, double>> angle;  // (degrees, area)
  angle.reserve(lod.positions.size());
  for (std::size_t i = 0; i < lod.positions.size(); ++i) {
    const ClosestPoint q = tree.Query(lod.positions[i]);
    if (q.triangle == kInvalidIndex || q.distance > near || !(area[i] > 0.0)) continue;
    const std::size_t t = 3 * static_cast<std::size_t>(q.triangle);
    const Vec3 n = q.barycentric.x * source.normals[source.indices[t]] +
                   q.barycentric.y * source.normals[source.indices[t + 1]] +
                   q.barycentric.z * source.normals[source.indices[t + 2]];
    const double ln = glm::length(n);
    if (!(ln > 0.0)) continue;
    const double c = std::clamp(glm::dot(n / ln, lod.normals[i]), -1.0, 1.0);
    angle.push_back({std::acos(c) * 180.0 / 3.14159265358979323846, area[i]});
  }
  if (angle.empty()) return;
  double sum = 0.0, total = 0.0;
  for (const auto& a : angle) sum += a.first * a.second, total += a.second;
  *mean = sum / total;
  std::sort(angle.begin(), angle.end());
  double below = 0.0;
  *p95 = angle.back().first;
  for (const auto& a : angle) {
    below += a.second;
    if (below >= 0.95 * total) {
      *p95 = a.first;
      break;
    }
  }
}

// Points on the triangles: the vertices and a barycentric grid of spacing about `h` inside.
std::vector<Vec3> SampleTriangles(const Triangles& m, double h) {
  std::vector<Vec3> out = m.positions;
  for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const Vec3 &a = m.positions[m.indices[t]], &b = m.positions[m.indices[t + 1]],
               &c = m.positions[m.indices[t + 2]];
    const double longest =
        std::max(glm::length(b - a), std::max(glm::length(c - b), glm::length(a - c)));
    const int k = std::min(32, static_cast<int>(std::ceil(longest / h)));
    for (int i = 0; i <= k; ++i) {
      for (int j = 0; i + j <= k; ++j) {
        const double u = double(i) / k, v = double(j) / k;
        out.push_back((1.0 - u - v) * a + u * b + v * c);
      }
    }
  }
  return out;
}

// --where: the largest distances of one direction, each with its place in the bounding box
// (0..1 per axis), and what the source is like at the nearest source point: on a boundary
// edge, and the largest dihedral angle (degrees) of the source triangle with its neighbours
// (a crease), and the source triangle's longest edge in % of the diagonal.
void PrintWorst(const char* what, const std::vector<Vec3>& points, const TriangleDistanceTree& tree,
                const TriangleDistanceTree& source_tree, const Triangles& source, const Vec3& lo,
                const Vec3& hi, double diagonal) {
  // Weld the source by position for its edges.
  std::map<std::array<double, 3>, std::uint32_t> weld;
  std::vector<std::uint32_t> id(source.positions.size());
  for (std::size_t v = 0; v < source.positions.size(); ++v) {
    const Vec3& x = source.positions[v];
    id[v] = weld.emplace(std::array<double, 3>{x.x, x.y, x.z}, static_cast<std::uint32_t>(v))
                .first->second;
  }
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::size_t>> edges;
  const std::size_t nt = source.indices.size() / 3;
  std::vector<Vec3> normal(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const Vec3 &a = source.positions[source.indices[3 * t]],
               &b = source.positions[source.indices[3 * t + 1]],
               &c = source.positions[source.indices[3 * t + 2]];
    const Vec3 n = glm::cross(b - a, c - a);
    const double l = glm::length(n);
    normal[t] = l > 0 ? n / l : Vec3(0.0);
    for (int k = 0; k < 3; ++k) {
      std::uint32_t x = id[source.indices[3 * t + static_cast<std::size_t>(k)]],
                    y = id[source.indices[3 * t + static_cast<std::size_t>((k + 1) % 3)]];
      edges[{std::min(x, y), std::max(x, y)}].push_back(t);
    }
  }
  std::vector<double> crease(nt, 0.0);
  std::vector<bool> boundary(nt, false);
  for (const auto& e : edges) {
    if (e.second.size() == 1) boundary[e.second[0]] = true;
    for (std::size_t i = 0; i < e.second.size(); ++i) {
      for (std::size_t j = 0; j < e.second.size(); ++j) {
        const double c = glm::clamp(glm::dot(normal[e.second[i]], normal[e.second[j]]), -1.0, 1.0);
        crease[e.second[i]] = std::max(crease[e.second[i]], std::acos(c) * 57.29577951308232);
      }
    }
  }
  std::vector<std::pair<double, std::size_t>> d(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) d[i] = {tree.Query(points[i]).distance, i};
  std::sort(d.begin(), d.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::printf("  worst %s:\n", what);
  std::vector<Vec3> shown;
  for (std::size_t k = 0; k < d.size() && shown.size() < 8; ++k) {
    const Vec3& p = points[d[k].second];
    bool near = false;
    for (const Vec3& q : shown) near = near || glm::length(p - q) < 0.03 * diagonal;
    if (near) continue;
    shown.push_back(p);
    const ClosestPoint cp = source_tree.Query(p);
    const std::size_t t = static_cast<std::size_t>(cp.triangle);
    const Vec3 &a = source.positions[source.indices[3 * t]],
               &b = source.positions[source.indices[3 * t + 1]],
               &c = source.positions[source.indices[3 * t + 2]];
    const double longest =
        std::max(glm::length(b - a), std::max(glm::length(c - b), glm::length(a - c)));
    const Vec3 r = (p - lo) / glm::max(hi - lo, Vec3(1e-30));
    std::printf(
        "    %.2f%% at (%.2f %.2f %.2f): source triangle %zu%s, crease %.0f deg, longest edge "
        "%.1f%%\n",
        100.0 * d[k].first / diagonal, r.x, r.y, r.z, t, boundary[t] ? " on a boundary" : "",
        crease[t], 100.0 * longest / diagonal);
  }
}

int RunCharacters(const Settings& st) {
  const char* names[] = {"RiggedSimple", "RiggedFigure", "Fox", "CesiumMan"};
  std::printf(
      "characters: `dermis fit` defaults, lod level 8 at rest against the source at rest, "
      "two-sided Hausdorff in %% of the source's bounding-box diagonal\n");
  std::printf(
      "| asset | source vertices (welded, fitted parts) | control vertices | Hausdorff %% | lod -> "
      "source max %% | source -> lod max %% | E1 max (model) | shading normals mean / p95 (deg) | "
      "integral of abs(H), lod / source | coefficients | fit (s) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const char* name : names) {
    // `--rows characters:Fox,CesiumMan` runs only the named ones.
    const std::size_t colon = st.rows.find("characters:");
    if (colon != std::string::npos && st.rows.find(name, colon) == std::string::npos) continue;
    const std::string path = std::string("../shared/data/gltf/") + name + ".glb";
    if (!std::filesystem::exists(path)) {
      std::printf("| %s | skipped: %s not found | | | | | | | | | |\n", name, path.c_str());
      continue;
    }
    Asset asset;
    Status s = ImportGltf(path, &asset);
    CharacterFitOptions options;
    ApplySettings(st, &options.fit);
    if (st.crease_smoothing >= 0.0) options.crease_smoothing = st.crease_smoothing;
    if (st.shading_shape >= 0.0) options.shading_shape = st.shading_shape;
    if (st.shading_max_move >= 0.0) options.shading_max_move = st.shading_max_move;
    if (st.vertex_weight > 0.0) options.vertex_weight = st.vertex_weight;
    if (st.samples >= 0.0) options.samples_per_control_edge = st.samples;
    if (st.crease_samples >= 0.0) options.crease_samples = st.crease_samples;
    if (st.crease_rows >= 0) options.crease_rows = st.crease_rows != 0;
    if (st.crease_angle >= 0.0) options.crease_angle = st.crease_angle;
    if (st.low_poly_crease_angle >= 0.0) options.low_poly_crease_angle = st.low_poly_crease_angle;
    if (st.max_turn >= 0.0) options.max_turn = st.max_turn;
    if (st.no_crease_remesh) options.remesh_creases = false;
    if (st.creases_ignore_shading) options.creases_follow_shading = false;
    if (st.no_check_shading) options.check_shading = false;
    if (st.crease_support >= 0.0) options.crease_support = st.crease_support;
    if (st.creases_closed) options.cut_creases = false;
    if (st.input_quads >= 0.0) options.input_quads = st.input_quads;
    if (st.compare_without_creases >= 0)
      options.compare_without_creases = st.compare_without_creases != 0;
    if (st.compare_simplified >= 0) options.compare_simplified = st.compare_simplified != 0;
    Character ch;
    CharacterFitReport report;
    if (s.ok()) s = FitCharacter(asset, options, &ch, &report);
    CharacterPoseOptions po;
    po.mode = CharacterPoseMode::kLod;
    po.level = 8;
    po.displacement_levels = st.displacement_levels;
    CharacterPoser poser;
    std::vector<PosedPrimitive> posed;
    if (s.ok()) s = CharacterPoser::Build(ch, po, &poser);
    if (s.ok()) s = poser.PoseClip(-1, 0.0, kDefaultPoseStepsPerSecond, &posed);
    if (!s.ok()) {
      std::fprintf(stderr, "bench_fit: %s: %s\n", name, s.message().c_str());
      return 1;
    }
    Triangles lod, source;
    for (std::size_t i = 0; i < posed.size(); ++i) {
      const DrawnPrimitive& d = poser.drawn()[i];
      const AssetPrimitive& prim = poser.asset()
                                       .meshes[static_cast<std::size_t>(d.mesh)]
                                       .primitives[static_cast<std::size_t>(d.primitive)];
      lod.Append(posed[i].positions, PrimitiveTriangles(prim), posed[i].normals);
    }
    AssetPose pose;
    RestPose(asset, &pose);
    std::vector<glm::dmat4> world;
    ComputeWorldMatrices(asset, pose, &world);
    for (std::size_t nd = 0; nd < asset.nodes.size(); ++nd) {
      const Index m = asset.nodes[nd].mesh;
      if (m == kInvalidIndex) continue;
      for (const AssetPrimitive& prim : asset.meshes[static_cast<std::size_t>(m)].primitives) {
        std::vector<glm::dvec3> x, nrm;
        PosePrimitive(asset, pose, world, static_cast<Index>(nd), prim, &x, &nrm);
        const std::vector<std::uint32_t> tris = PrimitiveTriangles(prim);
        if (nrm.size() == x.size()) {
          std::vector<Vec3> unit;
          for (const glm::dvec3& n : nrm) {
            const double l = glm::length(n);
            unit.push_back(l > 0.0 ? Vec3(n / l) : Vec3(0.0));
          }
          source.Append(x, tris, unit);
        } else {
          // No NORMAL attribute: glTF viewers shade each triangle flat.
          std::vector<Vec3> x3, n3;
          std::vector<std::uint32_t> t3;
          for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
            const Vec3 a = x[tris[t]], b = x[tris[t + 1]], c = x[tris[t + 2]];
            const Vec3 n = glm::cross(b - a, c - a);
            const double l = glm::length(n);
            for (const Vec3& v : {a, b, c}) {
              t3.push_back(static_cast<std::uint32_t>(x3.size()));
              x3.push_back(v);
              n3.push_back(l > 0.0 ? n / l : Vec3(0.0));
            }
          }
          source.Append(x3, t3, n3);
        }
      }
    }
    Vec3 lo(source.positions[0]), hi(lo);
    for (const Vec3& p : source.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const double diagonal = glm::length(hi - lo);
    TriangleDistanceTree source_tree, lod_tree;
    source_tree.Build(source.positions, source.indices);
    lod_tree.Build(lod.positions, lod.indices);
    double m1 = 0, x1 = 0, m2 = 0, x2 = 0;
    MeanMax(SampleTriangles(lod, diagonal / 400.0), source_tree, diagonal / 100.0, &m1, &x1);
    MeanMax(SampleTriangles(source, diagonal / 400.0), lod_tree, diagonal / 100.0, &m2, &x2);
    if (st.where) {
      PrintWorst("lod -> source", SampleTriangles(lod, diagonal / 400.0), source_tree, source_tree,
                 source, lo, hi, diagonal);
      PrintWorst("source -> lod", SampleTriangles(source, diagonal / 400.0), lod_tree, source_tree,
                 source, lo, hi, diagonal);
    }
    std::int64_t points = 0, control_vertices = 0, coefficients = 0;
    for (const CharacterPart& part : ch.parts) {
      points += part.fit.points;
      control_vertices += static_cast<std::int64_t>(part.surface.rest_positions.size());
      coefficients += part.fit.coefficients;
    }
    double shade_mean = -1.0, shade_p95 = -1.0;
    ShadingDeviation(lod, source, source_tree, diagonal / 100.0, &shade_mean, &shade_p95);
    // The integral of |mean curvature| (AbsMeanCurvatureIntegral): ripples and lumps add to it.
    const double curvature_ratio =
        AbsMeanCurvatureIntegral(lod.positions, lod.indices, 1e-7 * diagonal) /
        AbsMeanCurvatureIntegral(source.positions, source.indices, 1e-7 * diagonal);
    std::printf(
        "| %s | %lld | %lld | %.2f | %.2f | %.2f | %.3g | %.1f / %.1f | %.2f | %lld | %.2f |\n",
        name, static_cast<long long>(points), static_cast<long long>(control_vertices),
        std::max(x1, x2), x1, x2, report.e1_max, shade_mean, shade_p95, curvature_ratio,
        static_cast<long long>(coefficients), report.seconds);
    for (std::size_t p = 0; p < report.part_control_meshes.size(); ++p) {
      const ControlMeshInfo& c = report.part_control_meshes[p];
      std::printf(
          "  %s part %zu: %s, %d control vertices (target %d), valence 4 %.1f%%, corners "
          "%.1f..%.1f deg; creases: %d of %d source edges kept, %d chains (%d closed), %d "
          "control crease edges; support rows: %d loops, %d vertices moved; cut open: %d edges, "
          "%d vertices added; control-vertex fit: %d rounds; shading shape %.2f (normals %.2f deg "
          "from the shading normals, the flat triangles %.2f); creases from %.1f deg; surface "
          "gaps: %d source points added; check points: %d, levels dropped: %d by their distances, "
          "%d by their shading%s%s%s\n",
          name, p, c.method.c_str(), c.quality.vertices, c.quality.target_vertices,
          100.0 * c.quality.valence4_share, c.quality.min_corner_angle_deg,
          c.quality.max_corner_angle_deg, c.quality.crease_edges_kept, c.quality.crease_edges,
          c.quality.crease_chains, c.quality.crease_closed_chains, c.quality.control_crease_edges,
          c.crease_support_loops, c.crease_support_vertices, c.crease_cut_edges,
          c.crease_cut_vertices, c.control_fit_rounds, c.shading_shape, c.shading_deviation_deg,
          c.flat_deviation_deg, c.crease_angle_deg, c.surface_gap_points, c.check_points,
          c.check_levels_dropped, c.shading_levels_dropped,
          c.fallback.empty() ? "" : "; fallback: ", c.fallback.c_str(),
          c.quality.input_quads ? ("; the input's own quads (the remesh had " +
                                   std::to_string(c.quality.remesh_vertices) + " vertices)")
                                      .c_str()
                                : "");
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Settings st;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--control-vertices") == 0 && i + 1 < argc) {
      st.control_vertices = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--torus-vertices") == 0 && i + 1 < argc) {
      st.torus_vertices = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--torus-draws") == 0 && i + 1 < argc) {
      st.torus_draws = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--max-turn") == 0 && i + 1 < argc) {
      st.max_turn = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--samples") == 0 && i + 1 < argc) {
      st.samples = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--rows") == 0 && i + 1 < argc) {
      st.rows = argv[++i];
    } else if (std::strcmp(argv[i], "--control-method") == 0 && i + 1 < argc) {
      st.method = std::strcmp(argv[++i], "simplify") == 0 ? ControlMeshMethod::kSimplify
                                                          : ControlMeshMethod::kRemesh;
    } else if (std::strcmp(argv[i], "--density") == 0 && i + 1 < argc) {
      st.density = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--control-fit") == 0 && i + 1 < argc) {
      st.control_fit = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--tangent-weight") == 0 && i + 1 < argc) {
      st.tangent_weight = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--tangent-damping") == 0 && i + 1 < argc) {
      st.tangent_damping = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--noisy-ratio") == 0 && i + 1 < argc) {
      st.noisy_ratio = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--patch-agreement") == 0 && i + 1 < argc) {
      st.patch_agreement = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--no-cover-boundary") == 0) {
      st.no_cover_boundary = true;
    } else if (std::strcmp(argv[i], "--loop-segments") == 0 && i + 1 < argc) {
      st.loop_segments = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--chart-type") == 0 && i + 1 < argc) {
      const char* t = argv[++i];
      st.chart_type = std::strcmp(t, "complex") == 0       ? 1
                      : std::strcmp(t, "isodistance") == 0 ? 2
                                                           : 0;
    } else if (std::strcmp(argv[i], "--robust-cutoff") == 0 && i + 1 < argc) {
      st.robust_cutoff = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--finest-passes") == 0 && i + 1 < argc) {
      st.finest_passes = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--smoothing") == 0 && i + 1 < argc) {
      st.smoothing = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--detail") == 0) {
      st.detail = true;
    } else if (std::strcmp(argv[i], "--level-smoothing") == 0 && i + 1 < argc) {
      st.level_smoothing = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--crease-smoothing") == 0 && i + 1 < argc) {
      st.crease_smoothing = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--shading-max-move") == 0 && i + 1 < argc) {
      st.shading_max_move = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--shading-shape") == 0 && i + 1 < argc) {
      st.shading_shape = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--vertex-weight") == 0 && i + 1 < argc) {
      st.vertex_weight = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--crease-samples") == 0 && i + 1 < argc) {
      st.crease_samples = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--crease-rows") == 0 && i + 1 < argc) {
      st.crease_rows = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--displacement-levels") == 0 && i + 1 < argc) {
      st.displacement_levels = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--crease-angle") == 0 && i + 1 < argc) {
      st.crease_angle = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--low-poly-crease-angle") == 0 && i + 1 < argc) {
      st.low_poly_crease_angle = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--node-weight") == 0 && i + 1 < argc) {
      st.node_weight = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--budget") == 0 && i + 1 < argc) {
      st.budget = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--compare-without-creases") == 0 && i + 1 < argc) {
      st.compare_without_creases = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--no-crease-remesh") == 0) {
      st.no_crease_remesh = true;
    } else if (std::strcmp(argv[i], "--input-quads") == 0 && i + 1 < argc) {
      st.input_quads = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--creases-closed") == 0) {
      st.creases_closed = true;
    } else if (std::strcmp(argv[i], "--crease-support") == 0 && i + 1 < argc) {
      st.crease_support = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--no-check-shading") == 0) {
      st.no_check_shading = true;
    } else if (std::strcmp(argv[i], "--creases-ignore-shading") == 0) {
      st.creases_ignore_shading = true;
    } else if (std::strcmp(argv[i], "--compare-simplified") == 0 && i + 1 < argc) {
      st.compare_simplified = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--where") == 0) {
      st.where = true;
    } else if (std::strcmp(argv[i], "--mba") == 0) {
      st.mba = true;
    } else if (std::strcmp(argv[i], "--repeat") == 0 && i + 1 < argc) {
      st.repeat = std::max(1, std::atoi(argv[++i]));
    } else {
      st.bunny = argv[i];
    }
  }
  int rc = 0;
  if (st.Row("bunny")) rc |= RunBunny(st);
  if (st.Row("torus")) rc |= RunTorus(st);
  if (st.Row("characters")) rc |= RunCharacters(st);
  return rc;
}

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The fit of Yoon section 4 end to end, and its error metrics (docs/notes/fit.md section 3:
// E1 at the fitted parameters, E2 on held-out points, E3 two-sided Hausdorff, Metro style).
#include "dermis/offline/fit/surface_fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/trigonometric.hpp>
#include <limits>
#include <numeric>

#include "dermis/core/hash.h"
#include "dermis/core/parallel.h"
#include "dermis/offline/fit/boundary_cover.h"
#include "dermis/offline/fit/control_fit.h"
#include "dermis/offline/fit/lost_point_parameters.h"
#include "dermis/offline/fit/noise_estimate.h"
#include "dermis/offline/fit/point_fit.h"
#include "dermis/offline/fit/seam_displacement.h"
#include "dermis/offline/fit/shading_check.h"
#include "dermis/offline/fit/surface_projection.h"
#include "dermis/offline/geometry/triangle_distance.h"
#include "dermis/surface/surface_evaluator.h"
#include "dermis/surface/tessellation.h"

namespace dermis {
namespace {

using Clock = std::chrono::steady_clock;

// The stages' cost per data point, in points projected (FitPoints, the projection stage's
// work), rounded from the times measured on the Stanford bunny, the demo creature and
// RiggedSimple (docs/fitting.md, "Progress"): they only set how far the progress moves per
// stage.
constexpr std::size_t kControlMeshWork = 2;
constexpr std::size_t kControlRoundWork = 1;
constexpr std::size_t kDisplacementWork = 3;
constexpr std::size_t kMetricsWork = 6;
// Segments per face edge of the grid PlaceLostPoints starts from (docs/fitting.md, "Points the
// optimisation loses": 8 costs about 0.03 s on the bunny, 16 three times that for a largest E1
// a tenth lower).
constexpr int kLostPointGrid = 8;

double SecondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Gathers the samples of the given points, in point order.
std::vector<ChartSample> GatherSamples(const std::vector<PointFit>& fits, bool optimized) {
  std::vector<ChartSample> samples;
  samples.reserve(fits.size() * 4);
  for (const PointFit& f : fits) {
    if (f.status == PointFitStatus::kOutside) continue;
    if (optimized) {
      // Points whose solve failed (kNotConverged) have no optimised samples: they lie where
      // the detail folds over N~, and their per-chart projections contradict each other and
      // their neighbours, so they are left out of the optimised fit (still measured by E1).
      samples.insert(samples.end(), f.optimized, f.optimized + f.num_optimized);
    } else {
      samples.insert(samples.end(), f.projected, f.projected + f.num_projected);
    }
  }
  return samples;
}

std::unique_ptr<BsplineDisplacement> MakeDisplacement(const ManifoldDomain& domain,
                                                      const std::vector<ChartSample>& samples,
                                                      const DisplacementFitOptions& options,
                                                      Status* status) {
  return BsplineDisplacement::Create(FitDisplacements(domain, samples, options),
                                     domain.num_vertices(), status);
}

}  // namespace

bool IsHeldOut(std::size_t i, double fraction, std::uint64_t seed) {
  if (!(fraction > 0.0)) return false;
  const double u = HashToUnit(SplitMix64(seed ^ SplitMix64(i)));
  return u < fraction;
}

Status FitSurface(const FitInput& input, const FitOptions& options, FittedSurface* out,
                  FitReport* report) {
  const std::string where =
      input.mesh && !input.mesh->source_name.empty() ? input.mesh->source_name : "input";
  FitReport rep;
  rep.points = static_cast<std::int64_t>(input.points.size());
  rep.points_dropped = input.points_dropped;
  rep.threads = ResolveThreadCount(options.threads);
  if (input.points.empty()) return Status::InvalidInput(where + ": no data points to fit");
  if (!input.weights.empty()) {
    if (input.weights.size() != input.points.size()) {
      return Status::InvalidInput(where + ": " + std::to_string(input.weights.size()) +
                                  " point weights for " + std::to_string(input.points.size()) +
                                  " points");
    }
    for (std::size_t i = 0; i < input.weights.size(); ++i) {
      if (!(input.weights[i] > 0.0) || !std::isfinite(input.weights[i])) {
        return Status::InvalidInput(where + ": point " + std::to_string(i) +
                                    " has a weight that is not positive and finite");
      }
    }
  }
  for (std::size_t i = 0; i < input.check_points.size(); ++i) {
    const Vec3& p = input.check_points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      return Status::InvalidInput(where + ": check point " + std::to_string(i) + " is not finite");
    }
  }
  if (!input.check_normals.empty() && input.check_normals.size() != input.check_points.size()) {
    return Status::InvalidInput(where + ": " + std::to_string(input.check_normals.size()) +
                                " check normals for " + std::to_string(input.check_points.size()) +
                                " check points");
  }
  for (std::size_t i = 0; i < input.check_normals.size(); ++i) {
    const Vec3& n = input.check_normals[i];
    if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) {
      return Status::InvalidInput(where + ": check normal " + std::to_string(i) + " is not finite");
    }
    const double l = glm::length(n);
    if (l != 0.0 && std::abs(l - 1.0) > 1e-3) {
      return Status::InvalidInput(where + ": check normal " + std::to_string(i) +
                                  " is neither unit nor zero (length " + std::to_string(l) + ")");
    }
  }
  if (!input.check_normals.empty() &&
      !(options.displacement.adaptive.check_shading_tolerance >= 0.0 &&
        std::isfinite(options.displacement.adaptive.check_shading_tolerance))) {
    return Status::InvalidInput(where +
                                ": the check points' shading tolerance must be finite and not "
                                "negative");
  }
  Vec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
  for (std::size_t i = 0; i < input.points.size(); ++i) {
    const Vec3& p = input.points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      return Status::InvalidInput(where + ": point " + std::to_string(i) +
                                  " has a non-finite coordinate");
    }
    lo = glm::min(lo, p), hi = glm::max(hi, p);
  }
  const Vec3 ext = hi - lo;
  rep.scale = std::max(ext.x, std::max(ext.y, ext.z));
  if (!(rep.scale > 0.0)) return Status::InvalidInput(where + ": all points coincide");
  if (!(options.holdout >= 0.0 && options.holdout < 1.0)) {
    return Status::InvalidInput("holdout fraction must lie in [0, 1)");
  }
  const Clock::time_point t_total = Clock::now();
  // Progress (docs/fitting.md, "Progress"): each stage weighs its measured cost per data
  // point, in units of one point projected (FitPoints); skipped stages are jumped.
  const std::size_t n = input.points.size();
  const bool control_fit_planned = !input.control && options.control_fit_iterations > 0;
  // The control fit's regularisation follows the data's noise (FitOptions::
  // control_fit_noisy_ratio): full on a scan, none on an exact tessellation.
  ControlFitOptions control_fit = options.control_fit;
  int control_rounds = options.control_fit_iterations;
  if (control_fit_planned && input.mesh && options.control_fit_noisy_ratio > 0.0) {
    const VertexNoise noise = EstimateVertexNoise(*input.mesh);
    if (noise.vertices_used > 0) {
      rep.noise_ratio = noise.median_ratio;
      const double clean =
          std::min(options.control_fit_clean_ratio, options.control_fit_noisy_ratio);
      const double span = options.control_fit_noisy_ratio - clean;
      const double r = span > 0.0
                           ? std::clamp((rep.noise_ratio - clean) / span, 0.0, 1.0)
                           : (rep.noise_ratio >= options.control_fit_noisy_ratio ? 1.0 : 0.0);
      rep.control_fit_regularisation = r;
      if (control_fit.tangent_damping > control_fit.damping) {
        control_fit.tangent_damping =
            control_fit.damping + r * (control_fit.tangent_damping - control_fit.damping);
      }
      control_fit.patch_agreement *= r;
      control_rounds =
          static_cast<int>(std::lround(r * options.control_fit_iterations +
                                       (1.0 - r) * std::max(options.control_fit_iterations,
                                                            options.control_fit_clean_iterations)));
    }
  }
  const std::size_t rounds = control_fit_planned ? static_cast<std::size_t>(control_rounds) : 0;
  const std::size_t w_control_mesh = input.control ? n / 8 : kControlMeshWork * n;
  const std::size_t w_round = kControlRoundWork * n;
  const std::size_t w_projection = n;
  const std::size_t w_displacement = kDisplacementWork * n;
  const std::size_t w_metrics = kMetricsWork * n;
  const std::size_t work_total =
      w_control_mesh + rounds * w_round + w_projection + w_displacement + w_metrics;
  auto progress = [&](const char* stage, std::size_t done) {
    ReportProgress(options.progress, stage, std::min(done, work_total), work_total);
  };

  // 1. Control mesh, domain and rest patches.
  progress("control mesh", 0);
  Clock::time_point t0 = Clock::now();
  FittedSurface fitted;
  std::vector<std::uint8_t> seam;  // per control vertex, where the mesh was cut open
  if (input.control) {
    fitted.control_mesh = *input.control;
    CompactUnusedVertices(&fitted.control_mesh);
    rep.control_mesh.method = "given";
  } else {
    if (!input.mesh) {
      return Status::InvalidInput(where +
                                  ": a point cloud has no faces to build a control mesh from; "
                                  "give one with --control-mesh");
    }
    ControlMeshOptions cm;
    cm.target_vertices = options.control_vertices;
    cm.clamp_to_full_split = options.clamp_control_vertices;
    cm.method = options.control_method;
    cm.remesh = options.remesh;
    Status s = BuildControlMesh(*input.mesh, cm, &fitted.control_mesh, &rep.control_mesh);
    if (!s.ok()) return s;
    if (options.cut_control_mesh) {
      if (options.displacement.method != DisplacementMethod::kAdaptive) {
        return Status::InvalidInput(where +
                                    ": a control mesh cut open needs the adaptive displacement "
                                    "(its levels are made to vanish on the cut)");
      }
      s = options.cut_control_mesh(&fitted.control_mesh, &seam);
      if (!s.ok()) return s.WithContext(where);
      if (!seam.empty() && seam.size() != fitted.control_mesh.positions.size()) {
        return Status::Internal(
            where + ": the cut gave " + std::to_string(seam.size()) + " seam marks for " +
            std::to_string(fitted.control_mesh.positions.size()) + " control vertices");
      }
    }
    if (options.place_control_vertices) {
      const std::vector<Index> faces = fitted.control_mesh.face_vertices;
      const std::vector<Index> offsets = fitted.control_mesh.face_offsets;
      const std::size_t vertices = fitted.control_mesh.positions.size();
      options.place_control_vertices(&fitted.control_mesh);
      if (fitted.control_mesh.face_vertices != faces ||
          fitted.control_mesh.face_offsets != offsets ||
          fitted.control_mesh.positions.size() != vertices) {
        return Status::Internal(where + ": placing the control vertices changed the faces");
      }
    }
  }
  Status s = BuildControlSurface(fitted.control_mesh, options.domain, &fitted.surface,
                                 seam.empty() ? nullptr : &seam);
  if (!s.ok()) return s;
  const ManifoldDomain& domain = *fitted.surface.domain;
  const LocalPatch* patches = fitted.surface.patches.data();
  rep.control_vertices = domain.num_vertices();
  rep.control_faces = domain.num_faces();
  std::vector<Vec3> fit_points, holdout_points;
  std::vector<double> fit_weights;  // empty: every point 1
  const bool weighted = !input.weights.empty();
  for (std::size_t i = 0; i < input.points.size(); ++i) {
    if (IsHeldOut(i, options.holdout, options.holdout_seed)) {
      holdout_points.push_back(input.points[i]);
    } else {
      fit_points.push_back(input.points[i]);
      if (weighted) fit_weights.push_back(input.weights[i]);
    }
  }
  if (fit_points.empty()) return Status::InvalidInput(where + ": every point was held out");
  PointFitOptions pf;
  pf.threads = rep.threads;
  pf.tolerance = 1e-9 * rep.scale;
  // The control-vertex fit's rounds and the held-out points need the parameters only.
  PointFitOptions pf_parameters = pf;
  pf_parameters.chart_samples = false;
  // With residuals measured mostly across the surface (tangent weight below 1) the rounds take
  // Yoon's projection (the nearest corner's patch) and solve for the common displacement only
  // beside a boundary, where the point distance is kept: elsewhere a foot point off along the
  // surface costs little, and the solve was about two thirds of the projection's time
  // (docs/fitting.md, "The fit's time").
  PointFitOptions pf_rounds = pf_parameters;
  pf_rounds.optimize = !(control_fit.tangent_weight < 1.0);
  pf_rounds.optimize_beside_boundary = true;
  std::vector<PointFit> fits;
  // A built control mesh lies on the data; moving its vertices so that the smooth domain
  // surface follows the data leaves far smaller displacements at sharp and thin features. A
  // given control mesh is used as is.
  // The input's own quads (QuadRemeshOptions::input_quads_max_ratio) are the data's vertices,
  // which the domain surface interpolates: they stay.
  // A mesh cut open (FitOptions::cut_control_mesh) neither: the fit and the boundary cover move
  // each copy of a cut vertex on its own and would open the cut.
  if (!input.control && options.control_fit_iterations > 0 &&
      !rep.control_mesh.quality.input_quads && seam.empty() &&
      static_cast<double>(fit_points.size()) >=
          options.control_fit_min_points_per_vertex * domain.num_vertices()) {
    progress("control-vertex fit", w_control_mesh);
    ControlFitOptions cf = control_fit;
    cf.threads = rep.threads;
    std::vector<Vec3> x = fitted.surface.control.positions;
    for (int it = 0; it < control_rounds; ++it) {
      FitPoints(fitted.surface, fit_points, pf_rounds, &fits);
      // A round that cannot be solved (no usable data) leaves the positions of the last one.
      if (!FitControlPositions(domain, fit_points, fits, cf, &x).ok()) break;
      fitted.surface.control.positions = x;
      domain.FitPatches(x.data(), fitted.surface.patches.data());
      ++rep.control_fit_rounds;
      progress("control-vertex fit", w_control_mesh + rep.control_fit_rounds * w_round);
    }
    // A displacement along the normal cannot extend the surface: the data's boundary vertices
    // beyond the boundary curve would stay as far from the surface as from the curve.
    if (options.cover_boundary && input.mesh && rep.control_fit_rounds > 0 &&
        domain.topology().has_boundary()) {
      BoundaryCoverOptions bc;
      bc.threads = rep.threads;
      bc.tolerance = 1e-6 * rep.scale;
      // The held-out points' boundary vertices stay out of the fit (the mesh's vertices are
      // the points, in order).
      std::vector<Index> first;
      std::vector<std::pair<Vec3, Vec3>> edges = BoundaryEdges(*input.mesh, &first), kept;
      const bool same_order = input.mesh->positions.size() == input.points.size();
      for (std::size_t e = 0; e < edges.size(); ++e) {
        const auto i = static_cast<std::size_t>(first[e]);
        if (!same_order || !IsHeldOut(i, options.holdout, options.holdout_seed)) {
          kept.push_back(edges[e]);
        }
      }
      const BoundaryCoverReport cover = CoverDataBoundary(domain, kept, bc, &x);
      rep.boundary_points_beyond = cover.data_vertices_beyond;
      rep.boundary_largest_excess = cover.largest_excess / rep.scale;
      rep.boundary_vertices_moved = cover.vertices_moved;
      if (cover.vertices_moved > 0) {
        fitted.surface.control.positions = x;
        domain.FitPatches(x.data(), fitted.surface.patches.data());
      }
    }
    // A built control mesh is all quads, so its vertices are the quad mesh's.
    fitted.control_mesh.positions = fitted.surface.control.positions;
  } else {
    // No control-vertex fit ran (too few points per control vertex): no regularisation to
    // report.
    rep.noise_ratio = 0.0;
    rep.control_fit_regularisation = 1.0;
  }
  // A given control mesh's quality (a built one's is measured as built, before the fit).
  if (input.control) MeasureQuadMesh(fitted.control_mesh, &rep.control_mesh.quality);
  rep.seconds.control_mesh = SecondsSince(t0);

  // 2. Projection and optimisation of the fitted points.
  progress("projection and optimisation", w_control_mesh + rounds * w_round);
  t0 = Clock::now();
  FitPoints(fitted.surface, fit_points, pf, &fits);
  for (const PointFit& f : fits) {
    rep.points_outside += f.status == PointFitStatus::kOutside;
    rep.points_not_converged += f.status == PointFitStatus::kNotConverged;
  }
  rep.points_fitted = static_cast<std::int64_t>(fit_points.size()) - rep.points_outside;
  rep.points_holdout = static_cast<std::int64_t>(holdout_points.size());
  rep.seconds.projection_optimization = SecondsSince(t0);

  // 3. Displacement functions.
  progress("displacement functions", w_control_mesh + rounds * w_round + w_projection);
  t0 = Clock::now();
  DisplacementFitOptions dopt = options.displacement;
  dopt.threads = rep.threads;
  if (dopt.method == DisplacementMethod::kAdaptive) {
    std::vector<DisplacementTarget> targets;
    std::vector<std::size_t> target_point;
    MakeDisplacementTargets(domain, patches, fits, &targets, &target_point);
    if (weighted) {
      for (std::size_t k = 0; k < targets.size(); ++k) {
        targets[k].weight = fit_weights[target_point[k]];
      }
    }
    // The check points, projected and optimised as the fitted points (their common
    // displacement is what the levels bring them to).
    std::vector<PointFit> check_fits;
    if (!input.check_points.empty()) {
      FitPoints(fitted.surface, input.check_points, pf, &check_fits);
    }
    if (!input.check_points.empty() && input.check_distances) {
      std::vector<DisplacementTarget> check_targets;
      MakeDisplacementTargets(domain, patches, check_fits, &check_targets);
      for (DisplacementTarget& t : check_targets) {
        t.check = true;
        targets.push_back(t);
      }
    }
    std::vector<double> half(static_cast<std::size_t>(domain.num_vertices()));
    for (Index v = 0; v < domain.num_vertices(); ++v) {
      half[static_cast<std::size_t>(v)] =
          ChartHalfExtent(domain.chart(v), domain.options().blend_lb);
    }
    AdaptiveDisplacementOptions aopt = dopt.adaptive;
    aopt.max_levels = dopt.max_levels;
    aopt.threads = rep.threads;
    BsplineDisplacementData data;
    s = FitAdaptiveDisplacement(half, targets, aopt, &data, &rep.displacement_fit);
    if (!s.ok()) return s.WithContext(where);
    AdaptiveDisplacementReport& d = rep.displacement_fit;
    if (!input.check_normals.empty()) d.check_points = static_cast<std::int64_t>(check_fits.size());
    if (!seam.empty()) {
      s = ZeroDisplacementOnSeams(domain, seam, &data);
      if (!s.ok()) return s.WithContext(where);
    }
    fitted.displacement = BsplineDisplacement::Create(std::move(data), domain.num_vertices(), &s);
    if (!s.ok()) return s.WithContext(where);
    // The shading rule: the trailing levels that turn the normals away from the source's
    // shading at the check points are dropped. The levels are additive and the seams' change
    // is made level by level, so the first levels are exactly the fit with that many.
    if (!input.check_normals.empty() && fitted.displacement->max_levels() > 0) {
      const std::vector<double> angles = CheckPointNormalAngles(
          domain, patches, *fitted.displacement, check_fits, input.check_normals, rep.threads);
      for (double a : angles) d.check_angle_deg.push_back(glm::degrees(a));
      const int keep = ShadingCheckLevels(angles, aopt.check_shading_tolerance);
      if (keep < fitted.displacement->max_levels()) {
        d.shading_levels_dropped = fitted.displacement->max_levels() - keep;
        d.levels = keep;
        d.stopped_by = "check normals";
        d.level_nodes.resize(std::min(d.level_nodes.size(), static_cast<std::size_t>(keep)));
        // Each kept level stores one coefficient per active node (before the seams add any).
        d.coefficients =
            std::accumulate(d.level_nodes.begin(), d.level_nodes.end(), std::int64_t{0});
        fitted.displacement = BsplineDisplacement::Create(
            TruncateBsplineLevels(fitted.displacement->data(), keep), domain.num_vertices(), &s);
        if (!s.ok()) return s.WithContext(where);
      }
    }
  } else {
    fitted.displacement = MakeDisplacement(domain, GatherSamples(fits, true), dopt, &s);
  }
  if (!s.ok()) return s;
  // The points the optimisation could not place (left out of the displacement fit) take the
  // parameter of their closest point on the fitted surface.
  rep.points_not_converged_placed = PlaceLostPoints(domain, patches, fitted.displacement.get(),
                                                    fit_points, &fits, kLostPointGrid, rep.threads);
  rep.seconds.displacement = SecondsSince(t0);
  rep.seconds.total = SecondsSince(t_total);
  rep.coefficients = fitted.displacement->num_coefficients();
  rep.coefficients_per_point =
      static_cast<double>(rep.coefficients) / static_cast<double>(rep.points);
  rep.max_levels = fitted.displacement->max_levels();
  for (int k = 0; k < rep.max_levels; ++k) {
    rep.level_coefficients.push_back(fitted.displacement->level_coefficients(k));
  }
  {
    // Each chart's finest level: a dense lattice (merged), or its listed nodes (additive).
    const BsplineDisplacementData& dd = fitted.displacement->data();
    std::size_t g = 0;
    for (std::uint8_t l : dd.num_levels) {
      if (l == 0) continue;
      g += l;
      rep.finest_coefficients +=
          dd.form == BsplineLevelForm::kMerged ? BsplineLatticeSize(l - 1) : dd.level_counts[g - 1];
    }
  }

  // 4. Error metrics, in the unit where the data's largest side is 1.
  progress("error metrics", work_total - w_metrics);
  t0 = Clock::now();
  const Displacement* disp = fitted.displacement.get();
  const double inv = 1.0 / rep.scale;
  const int threads = rep.threads;
  // E1 at the fitted parameters, and the true distance from there.
  std::vector<double> e1(fits.size(), -1.0), closest(fits.size(), -1.0);
  ParallelFor(threads, fits.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const PointFit& f = fits[i];
      if (f.status == PointFitStatus::kOutside) continue;
      SurfacePoint sp;
      EvaluateSurface(domain, patches, disp, f.face, f.uv, &sp);
      e1[i] = std::sqrt(glm::dot(sp.position - fit_points[i], sp.position - fit_points[i]));
      Index face = f.face;
      Vec2 uv = f.uv;
      closest[i] = ClosestPointOnSurface(domain, patches, disp, fit_points[i], &face, &uv);
    }
  });
  double sum = 0.0, sum2 = 0.0, mx = 0.0, sum_closest = 0.0, count = 0.0;
  double input_to_surface = 0.0;  // Hausdorff half: data -> surface
  for (std::size_t i = 0; i < fits.size(); ++i) {
    if (e1[i] < 0.0) continue;
    sum += e1[i], sum2 += e1[i] * e1[i], mx = std::max(mx, e1[i]);
    sum_closest += closest[i];
    input_to_surface = std::max(input_to_surface, closest[i]);
    count += 1.0;
  }
  rep.error.mean = sum / count * inv;
  rep.error.rms = std::sqrt(sum2 / count) * inv;
  rep.error.max = mx * inv;
  rep.error.closest_mean = sum_closest / count * inv;
  // The paper's "without optimization": displacements fitted to the projections alone.
  {
    std::unique_ptr<BsplineDisplacement> unopt =
        MakeDisplacement(domain, GatherSamples(fits, false), dopt, &s);
    if (!s.ok()) return s;
    std::vector<double> eu(fits.size(), -1.0);
    ParallelFor(threads, fits.size(), [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        const PointFit& f = fits[i];
        if (f.status == PointFitStatus::kOutside) continue;
        SurfacePoint sp;
        EvaluateSurface(domain, patches, unopt.get(), f.projected_face, f.projected_uv, &sp);
        eu[i] = std::sqrt(glm::dot(sp.position - fit_points[i], sp.position - fit_points[i]));
      }
    });
    double su = 0.0;
    for (double v : eu) su += v >= 0.0 ? v : 0.0;
    rep.error.unoptimized_mean = su / count * inv;
  }
  // E2: held-out points, seeded by the same projection and optimisation on the domain.
  if (!holdout_points.empty()) {
    std::vector<PointFit> hfits;
    FitPoints(fitted.surface, holdout_points, pf_parameters, &hfits);
    // As the fitted points: a point the solve lost starts from its closest surface point.
    PlaceLostPoints(domain, patches, disp, holdout_points, &hfits, kLostPointGrid, threads);
    std::vector<double> eh(hfits.size(), -1.0);
    ParallelFor(threads, hfits.size(), [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        Index face = hfits[i].face;
        Vec2 uv = hfits[i].uv;
        if (hfits[i].status == PointFitStatus::kOutside) continue;
        eh[i] = ClosestPointOnSurface(domain, patches, disp, holdout_points[i], &face, &uv);
      }
    });
    double sh = 0.0, mh = 0.0, nh = 0.0;
    for (double v : eh) {
      if (v < 0.0) continue;
      sh += v, mh = std::max(mh, v), nh += 1.0;
      input_to_surface = std::max(input_to_surface, v);
    }
    rep.error.holdout_mean = nh > 0.0 ? sh / nh * inv : 0.0;
    rep.error.holdout_max = mh * inv;
  }
  // E3: two-sided Hausdorff against the input mesh: every data point to the surface (above),
  // and the surface, tessellated at level 8, to the mesh.
  if (input.mesh) {
    TriangleDistanceTree tree;
    tree.Build(input.mesh->positions, TriangulateFan(*input.mesh));
    TessellationPattern pattern;
    s = TessellationPattern::Build(domain.topology(), 8, &pattern);
    if (!s.ok()) return s;
    std::vector<Vec3> x(pattern.samples.size());
    EvaluateSamples(domain, patches, disp, pattern.samples.data(), x.size(), x.data(), nullptr);
    std::vector<double> d(x.size(), 0.0);
    ParallelFor(threads, x.size(), [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) d[i] = tree.Query(x[i]).distance;
    });
    const double surface_to_input = *std::max_element(d.begin(), d.end());
    Vec3 mlo(std::numeric_limits<double>::infinity()), mhi(-mlo);
    for (const Vec3& p : input.mesh->positions) mlo = glm::min(mlo, p), mhi = glm::max(mhi, p);
    const double diagonal = std::sqrt(glm::dot(mhi - mlo, mhi - mlo));
    const double h = std::max(surface_to_input, input_to_surface);
    rep.error.has_hausdorff = true;
    rep.error.hausdorff = h * inv;
    rep.error.hausdorff_percent_diagonal = 100.0 * h / diagonal;
  }
  rep.seconds.metrics = SecondsSince(t0);
  fitted.point_fits = std::move(fits);
  progress("error metrics", work_total);
  *out = std::move(fitted);
  if (report) *report = rep;
  return Status::Ok();
}

}  // namespace dermis

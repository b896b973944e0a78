// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Projection, the common-displacement solve, the whole fit on a synthetic shape with a known
// surface, .dsurf round trips, determinism across threads and bad inputs.
#include "dermis/offline/fit/surface_fit.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "dermis/dsurf/dsurf.h"
#include "dermis/offline/build/control_mesh.h"
#include "dermis/offline/fit/boundary_cover.h"
#include "dermis/offline/fit/lost_point_parameters.h"
#include "dermis/offline/fit/point_fit.h"
#include "dermis/offline/fit/surface_projection.h"
#include "dermis/offline/geometry/builtin_meshes.h"
#include "dermis/offline/geometry/triangle_distance.h"
#include "dermis/offline/io/point_input.h"
#include "dermis/surface/chart.h"
#include "dermis/surface/surface_evaluator.h"
#include "dermis/surface/tessellation.h"
#include "test_meshes.h"

using namespace dermis;
using namespace dermis::test;

namespace {

// A bumpy sphere: radius 1 + a sin(3 theta) sin(2 phi) around the origin.
Vec3 Bumpy(double theta, double phi, double a) {
  const double r = 1.0 + a * std::sin(3.0 * theta) * std::sin(2.0 * phi);
  return r * Vec3(std::sin(phi) * std::cos(theta), std::sin(phi) * std::sin(theta), std::cos(phi));
}

PolygonMesh Cube(double half) {
  PolygonMesh m = Builtin("cube");
  for (Vec3& p : m.positions) p *= half;  // builtin cube is [-1, 1]^3
  return m;
}

// The shared Stanford bunny scan as `dermis fit` reads it; false, with a warning, where
// ../shared/data is absent (the [heavy] cases then skip).
bool ReadSharedBunny(PolygonMesh* mesh, Index* dropped) {
  const std::string path = "../shared/data/scans/stanford-bunny.obj";
  if (!std::ifstream(path)) {
    WARN("skipped: " << path << " not found (run from the repo root with ../shared/data)");
    return false;
  }
  REQUIRE(ReadFitInput(path, mesh, dropped).ok());
  return true;
}

// The built-in grid's surface (4 x 3 quads, open) and, as an independent reference for
// point-to-surface distances, its level-64 tessellation in a distance tree (exact
// point-to-triangle distances; the chords lie within about 3e-5 of the surface).
void GridAndReference(ControlSurface* surface, TriangleDistanceTree* reference) {
  PolygonMesh grid;
  REQUIRE(MakeBuiltinMesh("grid", &grid).ok());
  REQUIRE(BuildControlSurface(grid, DomainOptions(), surface).ok());
  TessellationPattern pattern;
  REQUIRE(TessellationPattern::Build(surface->domain->topology(), 64, &pattern).ok());
  std::vector<Vec3> xs(pattern.samples.size());
  REQUIRE(EvaluateSamples(*surface->domain, surface->patches.data(), nullptr,
                          pattern.samples.data(), xs.size(), xs.data(), nullptr));
  REQUIRE(reference->Build(xs, pattern.triangles));
}

}  // namespace

TEST_CASE("fit: projection converges on an analytic patch") {
  LocalPatch patch;
  patch.coeff[0][0] = Vec3(0.1, -0.2, 0.3);
  patch.coeff[1][0] = Vec3(1.0, 0.1, 0.0);
  patch.coeff[0][1] = Vec3(0.0, 1.0, 0.2);
  patch.coeff[2][0] = Vec3(0.0, 0.0, 0.4);
  patch.coeff[0][2] = Vec3(0.0, 0.0, -0.3);
  patch.coeff[1][1] = Vec3(0.0, 0.0, 0.25);
  patch.coeff[2][2] = Vec3(0.05, 0.0, 0.0);
  Lcg rng(5);
  for (int n = 0; n < 200; ++n) {
    const Vec2 z(rng.Uniform(-0.5, 0.5), rng.Uniform(-0.5, 0.5));
    PatchFrame f;
    EvaluatePatchFrame(patch, z, &f);
    const double d = rng.Uniform(-0.1, 0.1);  // within the focal distance
    const Vec3 p = f.p + d * f.n;
    const Vec2 guess = z + Vec2(rng.Uniform(-0.15, 0.15), rng.Uniform(-0.15, 0.15));
    const Vec2 found = ProjectOntoPatch(patch, p, guess, 20);
    CHECK(found.x == Approx(z.x).margin(1e-9));
    CHECK(found.y == Approx(z.y).margin(1e-9));
  }
}

TEST_CASE("fit: the common-displacement solve inverts Q + delta N") {
  PolygonMesh torus = Builtin("torus");
  Perturb(&torus, 0.05, 9);
  ControlSurface s = Build(torus);
  const ManifoldDomain& domain = *s.domain;
  Lcg rng(17);
  int solved = 0;
  for (int n = 0; n < 200; ++n) {
    const Index face = static_cast<Index>(rng.Next() * domain.num_faces());
    const Vec2 uv(rng.Uniform(0.02, 0.98), rng.Uniform(0.02, 0.98));
    const int a = DominantCorner(uv);
    const Index v = domain.topology().face_vertex(face, a);
    DomainJet jet;
    REQUIRE(EvaluateDomainJet(domain, s.patches.data(), v, domain.FaceToChart(face, a, uv), &jet));
    const double delta = rng.Uniform(-0.02, 0.02);
    const Vec3 p = jet.q + delta * jet.n;
    // Start from a nearby corner's chart, off by a little.
    const Vec2 z0 =
        domain.FaceToChart(face, a, glm::clamp(uv + Vec2(0.05, -0.04), Vec2(0.0), Vec2(1.0)));
    const CommonDisplacementSolution sol =
        SolveCommonDisplacement(domain, s.patches.data(), p, v, z0, 0.0, 1e-12);
    if (!sol.converged) continue;
    ++solved;
    SurfacePoint sp;
    // Same point of the surface (possibly expressed in a neighbouring face).
    REQUIRE(sol.residual <= 1e-12);
    CHECK(sol.delta == Approx(delta).margin(1e-9));
    DomainJet check;
    const int b = DominantCorner(sol.uv);
    REQUIRE(EvaluateDomainJet(domain, s.patches.data(), domain.topology().face_vertex(sol.face, b),
                              domain.FaceToChart(sol.face, b, sol.uv), &check));
    CHECK(glm::length(check.q - jet.q) < 1e-9);
  }
  CHECK(solved >= 190);
}

TEST_CASE("fit: domain jet derivatives match finite differences") {
  PolygonMesh house = Builtin("house");
  Perturb(&house, 0.05, 4);
  ControlSurface s = Build(house);
  const ManifoldDomain& domain = *s.domain;
  Lcg rng(23);
  for (int n = 0; n < 100; ++n) {
    const Index face = static_cast<Index>(rng.Next() * domain.num_faces());
    const Vec2 uv(rng.Uniform(0.1, 0.9), rng.Uniform(0.1, 0.9));
    const int a = DominantCorner(uv);
    const Index v = domain.topology().face_vertex(face, a);
    const Vec2 z = domain.FaceToChart(face, a, uv);
    DomainJet j, jx0, jx1, jy0, jy1;
    const double h = 1e-6;
    REQUIRE(EvaluateDomainJet(domain, s.patches.data(), v, z, &j));
    REQUIRE(EvaluateDomainJet(domain, s.patches.data(), v, z - Vec2(h, 0), &jx0));
    REQUIRE(EvaluateDomainJet(domain, s.patches.data(), v, z + Vec2(h, 0), &jx1));
    REQUIRE(EvaluateDomainJet(domain, s.patches.data(), v, z - Vec2(0, h), &jy0));
    REQUIRE(EvaluateDomainJet(domain, s.patches.data(), v, z + Vec2(0, h), &jy1));
    CHECK(glm::length((jx1.q - jx0.q) / (2 * h) - j.qx) < 1e-5);
    CHECK(glm::length((jy1.q - jy0.q) / (2 * h) - j.qy) < 1e-5);
    CHECK(glm::length((jx1.n - jx0.n) / (2 * h) - j.nx) < 1e-4);
    CHECK(glm::length((jy1.n - jy0.n) / (2 * h) - j.ny) < 1e-4);
    // Q agrees with the runtime evaluator.
    SurfacePoint sp;
    REQUIRE(EvaluateSurface(domain, s.patches.data(), nullptr, j.face, j.uv, &sp));
    CHECK(glm::length(sp.position - j.q) < 1e-12);
  }
}

TEST_CASE("fit: a bumpy sphere over a cube control mesh is recovered") {
  const PolygonMesh dense = BumpySphereMesh(160, 80, 0.05);
  const PolygonMesh control = Cube(0.62);
  FitInput input;
  input.points = dense.positions;
  input.mesh = &dense;
  input.control = &control;
  FitOptions options;
  options.threads = 2;
  FittedSurface fitted;
  FitReport report;
  const Status s = FitSurface(input, options, &fitted, &report);
  REQUIRE(s.ok());
  INFO("E1 " << report.error.mean << " held out " << report.error.holdout_mean << " hausdorff "
             << report.error.hausdorff << " outside " << report.points_outside);
  CHECK(report.points == dense.num_vertices());
  CHECK(report.points_outside == 0);
  CHECK(report.control_vertices == 8);
  CHECK(report.error.unoptimized_mean > report.error.mean);
  // Unit: the sphere's largest side is about 2, so 1e-3 is 0.1% of the size; the bumps are 5%.
  CHECK(report.error.mean < 2e-4);
  CHECK(report.error.holdout_mean < 1e-3);
  CHECK(report.error.hausdorff < 1e-2);
  // Independently: fresh points of the known shape lie close to the fitted surface.
  TessellationPattern pattern;
  REQUIRE(TessellationPattern::Build(fitted.surface.domain->topology(), 24, &pattern).ok());
  std::vector<Vec3> x(pattern.samples.size());
  REQUIRE(EvaluateSamples(*fitted.surface.domain, fitted.surface.patches.data(),
                          fitted.displacement.get(), pattern.samples.data(), x.size(), x.data(),
                          nullptr));
  double worst = 0.0;
  for (const Vec3& p : x) {
    // Distance to the analytic surface along the radius (a tight bound for small bumps).
    const double r = glm::length(p);
    const double phi = std::acos(p.z / r), theta = std::atan2(p.y, p.x);
    worst = std::max(worst, std::abs(r - glm::length(Bumpy(theta, phi, 0.05))));
  }
  CHECK(worst < 5e-3);
}

// The bumpy sphere whose rings of vertices are moved off it along the radius by 0.5 % in turn
// (the finest levels follow them and swing between them), on a cube's control mesh, fitted as a
// character's part is: every point fitted, no validation split. The check point tests share it.
struct RingsOff {
  PolygonMesh dense = BumpySphereMesh(80, 40, 0.05);
  PolygonMesh control = Cube(0.62);
  FitInput Input() const {
    FitInput input;
    input.points = dense.positions;
    for (std::size_t i = 0; i < input.points.size(); ++i) {
      input.points[i] *= (i / 80) % 2 == 0 ? 1.005 : 0.995;
    }
    input.mesh = &dense;
    input.control = &control;
    return input;
  }
  static FitOptions Options() {
    FitOptions options;
    options.threads = 2;
    options.holdout = 0.0;
    options.displacement.adaptive.validation = 0.0;
    return options;
  }
  // The analytic surface's point between the vertices for check point (i, j), i < 40, 0 < j < 20.
  static Vec3 CheckPoint(int i, int j) {
    return Bumpy(2.0 * M_PI * (i + 0.37) / 40.0, M_PI * (j + 0.41) / 20.0, 0.05);
  }
};

// `kept` is `full`'s first `levels` levels: the same value at points of the cube's 8 charts.
void CheckFirstLevels(const BsplineDisplacement& full, int levels,
                      const BsplineDisplacement& kept) {
  const TruncatedDisplacement truncated(&full, levels);
  for (Index c = 0; c < 8; ++c) {
    for (int k = 0; k < 25; ++k) {
      const Vec2 z(-0.3 + 0.15 * (k % 5), -0.3 + 0.15 * (k / 5));
      double a = 0.0, b = 0.0;
      Vec2 ga, gb;
      truncated.Evaluate(c, z, &a, &ga);
      kept.Evaluate(c, z, &b, &gb);
      CHECK(a == Approx(b).margin(1e-15));
    }
  }
}

TEST_CASE("fit: check points are projected, never fitted, and only truncate the levels") {
  // The bumpy sphere as above, its rings of vertices moved off it along the radius by 0.5 %
  // in turn (the finest levels follow them and swing between them), fitted as a character's
  // part is (no validation split), once without and once with check points on the analytic
  // surface between the vertices.
  const RingsOff r;
  FitInput input = r.Input();
  const FitOptions options = RingsOff::Options();
  FittedSurface plain_fit, checked_fit;
  FitReport plain, checked;
  REQUIRE(FitSurface(input, options, &plain_fit, &plain).ok());
  for (int i = 0; i < 40; ++i) {
    for (int j = 1; j < 20; ++j) {
      input.check_points.push_back(RingsOff::CheckPoint(i, j));
    }
  }
  REQUIRE(FitSurface(input, options, &checked_fit, &checked).ok());
  const AdaptiveDisplacementReport &dp = plain.displacement_fit, &dc = checked.displacement_fit;
  INFO("levels " << dp.levels << " -> " << dc.levels << " (" << dc.stopped_by << ")");
  CHECK(dp.check_points == 0);
  CHECK(dp.check_mean.empty());
  // Every check point projected and optimised (a sphere: none lost), measured with no level
  // and after each level the fit without them kept.
  CHECK(dc.check_points == static_cast<std::int64_t>(input.check_points.size()));
  CHECK(dc.check_mean.size() == static_cast<std::size_t>(dp.levels) + 1);
  // Measured: the check points' error falls to 0.0012 with 6 levels, then rises with the
  // 2 finest (0.0028, 0.0033): those are dropped.
  CHECK(dc.levels >= 1);
  CHECK(dc.levels < dp.levels);
  CHECK(dc.stopped_by == "check points");
  CHECK(checked.coefficients < plain.coefficients);
  // Never fitted: the surface is the plain fit's first levels.
  const BsplineDisplacement* full = plain_fit.displacement.get();
  const BsplineDisplacement* kept = checked_fit.displacement.get();
  REQUIRE(full);
  REQUIRE(kept);
  CheckFirstLevels(*full, dc.levels, *kept);
}

TEST_CASE("fit: check normals drop the trailing levels that turn the surface's normals away") {
  // The set-up above, the check points now carrying the analytic surface's normals
  // (FitInput::check_normals; docs/characters.md, "Levels checked by the shading"): after the
  // distance rule, the trailing levels whose normals stray further from them are dropped.
  const RingsOff r;
  FitInput input = r.Input();
  const FitOptions options = RingsOff::Options();
  for (int i = 0; i < 40; ++i) {
    for (int j = 1; j < 20; ++j) {
      const double t = 2.0 * M_PI * (i + 0.37) / 40.0, p = M_PI * (j + 0.41) / 20.0, h = 1e-6;
      input.check_points.push_back(Bumpy(t, p, 0.05));
      // The normal from central differences of the analytic surface, outwards.
      const Vec3 n = glm::normalize(glm::cross(Bumpy(t + h, p, 0.05) - Bumpy(t - h, p, 0.05),
                                               Bumpy(t, p + h, 0.05) - Bumpy(t, p - h, 0.05)));
      input.check_normals.push_back(glm::dot(n, input.check_points.back()) > 0.0 ? n : -n);
    }
  }
  FittedSurface distance_fit, shading_fit;
  FitReport distance, shading;
  FitInput no_normals = input;
  no_normals.check_normals.clear();
  REQUIRE(FitSurface(no_normals, options, &distance_fit, &distance).ok());
  REQUIRE(FitSurface(input, options, &shading_fit, &shading).ok());
  const AdaptiveDisplacementReport &dd = distance.displacement_fit, &ds = shading.displacement_fit;
  CHECK(dd.check_angle_deg.empty());
  CHECK(dd.shading_levels_dropped == 0);
  // The angles with no level and each level the distance rule kept.
  REQUIRE(ds.check_angle_deg.size() == static_cast<std::size_t>(dd.levels) + 1);
  INFO("levels " << dd.levels << " -> " << ds.levels << "; angles (deg) with 0.." << dd.levels
                 << " levels: " << ds.check_angle_deg.front() << " .. "
                 << ds.check_angle_deg.back());
  CHECK(ds.levels + ds.shading_levels_dropped == dd.levels);
  // Here every level follows the sphere's real bumps and brings the normals closer (measured:
  // 15.5 degrees on the domain surface, 1.65 with the 6 levels): none is dropped.
  CHECK(ds.shading_levels_dropped == 0);
  // The rule: each dropped level turned the normals further away, the last kept did not.
  for (int l = ds.levels + 1; l <= dd.levels; ++l) {
    CHECK(ds.check_angle_deg[static_cast<std::size_t>(l)] >
          ds.check_angle_deg[static_cast<std::size_t>(l) - 1]);
  }
  if (ds.levels > 0) {
    CHECK(ds.check_angle_deg[static_cast<std::size_t>(ds.levels)] <=
          ds.check_angle_deg[static_cast<std::size_t>(ds.levels) - 1]);
  }
  // The levels bring the normals closer than the domain surface's (the bumps are real).
  CHECK(ds.check_angle_deg[static_cast<std::size_t>(ds.levels)] < ds.check_angle_deg[0]);
  // The surface is the distance rule's first levels, and the report counts what is stored.
  CheckFirstLevels(*distance_fit.displacement, ds.levels, *shading_fit.displacement);
  CHECK(shading.coefficients == shading_fit.displacement->num_coefficients());
  CHECK(ds.coefficients == shading.coefficients);
}

TEST_CASE("fit: check normals of a smoother surface drop the levels that follow the bumps") {
  // The bumpy sphere's points (its rings 0.5 % off in turn, as above) with check points on it
  // whose normals are those of the plain sphere (radial): the levels that take in the bumps
  // turn the surface's normals away from these, and the shading rule drops them. Its own
  // distances alone (check_distances false) do not decide: the report's check_mean is empty.
  const RingsOff r;
  FitInput input = r.Input();
  const FitOptions options = RingsOff::Options();
  FittedSurface plain_fit, fit;
  FitReport plain, report;
  REQUIRE(FitSurface(input, options, &plain_fit, &plain).ok());
  for (int i = 0; i < 40; ++i) {
    for (int j = 1; j < 20; ++j) {
      const Vec3 p = RingsOff::CheckPoint(i, j);
      input.check_points.push_back(p);
      input.check_normals.push_back(glm::normalize(p));
    }
  }
  input.check_distances = false;
  REQUIRE(FitSurface(input, options, &fit, &report).ok());
  const AdaptiveDisplacementReport& d = report.displacement_fit;
  INFO("levels " << plain.displacement_fit.levels << " -> " << d.levels << " (" << d.stopped_by
                 << "), angles " << d.check_angle_deg.front() << " .. "
                 << d.check_angle_deg.back());
  CHECK(d.check_mean.empty());
  CHECK(d.check_points == static_cast<std::int64_t>(input.check_points.size()));
  REQUIRE(d.check_angle_deg.size() == static_cast<std::size_t>(plain.displacement_fit.levels) + 1);
  REQUIRE(d.shading_levels_dropped >= 1);
  CHECK(d.levels + d.shading_levels_dropped == plain.displacement_fit.levels);
  CHECK(d.stopped_by == "check normals");
  for (int l = d.levels + 1; l <= plain.displacement_fit.levels; ++l) {
    CHECK(d.check_angle_deg[static_cast<std::size_t>(l)] >
          d.check_angle_deg[static_cast<std::size_t>(l) - 1]);
  }
  // The report describes what is stored.
  const BsplineDisplacement& kept = *fit.displacement;
  CHECK(kept.max_levels() == d.levels);
  CHECK(report.max_levels == d.levels);
  CHECK(d.level_nodes.size() == static_cast<std::size_t>(d.levels));
  CHECK(report.coefficients == kept.num_coefficients());
  CHECK(d.coefficients == kept.num_coefficients());  // no seam here
  REQUIRE(report.level_coefficients.size() == static_cast<std::size_t>(d.levels));
  std::int64_t sum = 0;
  for (int k = 0; k < d.levels; ++k) {
    CHECK(report.level_coefficients[static_cast<std::size_t>(k)] ==
          plain.level_coefficients[static_cast<std::size_t>(k)]);
    sum += report.level_coefficients[static_cast<std::size_t>(k)];
  }
  CHECK(sum == report.coefficients);
  CHECK(report.coefficients < plain.coefficients);
  // The surface is the plain fit's first levels...
  CheckFirstLevels(*plain_fit.displacement, d.levels, kept);
  // ... and E1 is measured on it: the fitted points' mean distance at their parameters.
  double e1 = 0.0, count = 0.0;
  for (std::size_t i = 0; i < fit.point_fits.size(); ++i) {
    const PointFit& f = fit.point_fits[i];
    if (f.status == PointFitStatus::kOutside) continue;
    SurfacePoint sp;
    REQUIRE(
        EvaluateSurface(*fit.surface.domain, fit.surface.patches.data(), &kept, f.face, f.uv, &sp));
    e1 += glm::length(sp.position - input.points[i]);
    count += 1.0;
  }
  CHECK(e1 / count / report.scale == Approx(report.error.mean).epsilon(1e-9));
  // Measured: 8 levels -> 3 (angles 12.97 degrees on the domain surface, 4.74 with 3 levels,
  // 10.19 with 8), 9,366 -> 409 coefficients, E1 5.5e-4 -> 8.7e-3.
  CHECK(report.error.mean > plain.error.mean);  // the bumps' levels are gone
}

TEST_CASE("fit: FitPoints without chart samples gives the same parameters") {
  // The control-vertex fit's rounds and the held-out points skip the per-chart projections
  // (PointFitOptions::chart_samples); the parameters, statuses and deltas must not change.
  const PolygonMesh dense = BumpySphereMesh(40, 20, 0.05);
  ControlSurface surface;
  REQUIRE(BuildControlSurface(Cube(0.62), DomainOptions(), &surface).ok());
  PointFitOptions with, without;
  with.threads = without.threads = 2;
  with.tolerance = without.tolerance = 1e-9;
  without.chart_samples = false;
  std::vector<PointFit> a, b;
  FitPoints(surface, dense.positions, with, &a);
  FitPoints(surface, dense.positions, without, &b);
  REQUIRE(a.size() == dense.positions.size());
  REQUIRE(b.size() == a.size());
  int optimized = 0, sampled = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    INFO("point " << i);
    CHECK(a[i].status == b[i].status);
    CHECK(a[i].face == b[i].face);
    CHECK(a[i].uv == b[i].uv);
    CHECK(a[i].delta == b[i].delta);
    CHECK(a[i].projected_face == b[i].projected_face);
    CHECK(a[i].projected_uv == b[i].projected_uv);
    CHECK(a[i].num_optimized == b[i].num_optimized);
    CHECK(b[i].num_projected == 0);
    optimized += a[i].status == PointFitStatus::kOptimized;
    sampled += a[i].num_projected > 0;
  }
  // The comparison means something: most points were optimised and had chart samples.
  CHECK(optimized > static_cast<int>(a.size()) * 9 / 10);
  CHECK(sampled > static_cast<int>(a.size()) * 9 / 10);
}

TEST_CASE("fit: FitPoints can solve only beside a boundary") {
  // The control-vertex fit's rounds solve for the common displacement only in faces with a
  // boundary vertex (PointFitOptions::optimize_beside_boundary): there the parameters must be
  // the full solve's, elsewhere the projection's. The built-in grid (4 x 3 quads, open) has
  // two faces without a boundary vertex.
  PolygonMesh grid;
  REQUIRE(MakeBuiltinMesh("grid", &grid).ok());
  ControlSurface surface;
  REQUIRE(BuildControlSurface(grid, DomainOptions(), &surface).ok());
  const ManifoldDomain& domain = *surface.domain;
  std::vector<Vec3> points;
  for (Index f = 0; f < domain.num_faces(); ++f) {
    for (int j = 0; j < 6; ++j) {
      for (int i = 0; i < 6; ++i) {
        SurfacePoint sp;
        REQUIRE(EvaluateSurface(domain, surface.patches.data(), nullptr, f,
                                Vec2((i + 0.5) / 6, (j + 0.5) / 6), &sp));
        points.push_back(sp.position + 0.05 * std::sin(3.0 * sp.position.x) * sp.normal);
      }
    }
  }
  auto beside_boundary = [&](Index face) {
    for (int a = 0; a < 4; ++a) {
      if (domain.topology().is_boundary_vertex(domain.topology().face_vertex(face, a))) {
        return true;
      }
    }
    return false;
  };
  PointFitOptions full, boundary_only, none;
  full.threads = boundary_only.threads = none.threads = 2;
  full.chart_samples = boundary_only.chart_samples = none.chart_samples = false;
  boundary_only.optimize = none.optimize = false;
  boundary_only.optimize_beside_boundary = true;
  std::vector<PointFit> a, b, c;
  FitPoints(surface, points, full, &a);
  FitPoints(surface, points, boundary_only, &b);
  FitPoints(surface, points, none, &c);
  REQUIRE(b.size() == points.size());
  int solved = 0, projected = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    INFO("point " << i);
    CHECK(c[i].status != PointFitStatus::kOptimized);
    // Solved exactly as the full solve where the projection's face has a boundary vertex or
    // no projection stayed in its chart; the projection's parameter elsewhere.
    const bool solve = c[i].status == PointFitStatus::kOutside || beside_boundary(c[i].face);
    if (solve) {
      ++solved;
      CHECK(b[i].status == a[i].status);
      CHECK(b[i].face == a[i].face);
      CHECK(b[i].uv == a[i].uv);
      CHECK(b[i].delta == a[i].delta);
    } else {
      ++projected;
      CHECK(b[i].status == c[i].status);
      CHECK(b[i].face == c[i].face);
      CHECK(b[i].uv == c[i].uv);
      CHECK(b[i].face == a[i].projected_face);
      CHECK(b[i].uv == a[i].projected_uv);
    }
  }
  // Both kinds occur: 10 of the 12 faces have a boundary vertex.
  CHECK(solved > static_cast<int>(points.size()) / 2);
  CHECK(projected > static_cast<int>(points.size()) / 12);
}

TEST_CASE("fit: PlaceLostPoints gives a lost point its closest surface point") {
  // Points near the built-in grid's saddle (4 x 3 quads, open) and beyond its boundary, marked
  // not converged at a wrong parameter (a far corner of a face sharing a vertex with theirs,
  // or of their own face at the grid's corners, as a projection onto the wrong patch gives):
  // afterwards the
  // surface at their parameter is as close to them as a level-64 tessellation of the surface
  // says it can be (an independent exact point-to-triangle distance). Optimised and outside
  // fits are left alone, and the thread count changes nothing.
  ControlSurface surface;
  TriangleDistanceTree tree;
  GridAndReference(&surface, &tree);
  const ManifoldDomain& domain = *surface.domain;
  const LocalPatch* patches = surface.patches.data();
  const MeshTopology& topo = domain.topology();
  std::vector<Vec3> points;
  std::vector<PointFit> fits;
  for (Index f = 0; f < domain.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Vec2 uv(0.2 + 0.3 * k, 0.7 - 0.25 * k);
      SurfacePoint sp;
      REQUIRE(EvaluateSurface(domain, patches, nullptr, f, uv, &sp));
      PointFit fit;
      fit.status = PointFitStatus::kNotConverged;
      const RingCorner rc = topo.ring(topo.face_vertex(f, k + 1), 0);
      fit.face = rc.face != f ? rc.face
                              : topo.ring(topo.face_vertex(f, k + 1),
                                          topo.valence(topo.face_vertex(f, k + 1)) - 1)
                                    .face;
      fit.uv = Vec2(k == 1 ? 0.95 : 0.05, 0.9);
      // Off the surface along its normal, and for k = 2 also outward past the boundary.
      Vec3 p = sp.position + (0.03 - 0.02 * k) * sp.normal;
      if (k == 2 && topo.face_touches_boundary(f)) p += 0.8 * glm::normalize(Vec3(p.x, p.y, 0.0));
      points.push_back(p);
      fits.push_back(fit);
    }
  }
  // One optimised and one outside fit, a lost one without a face and a lost point that is not
  // finite: none of them may move.
  PointFit optimised = fits[0], outside = fits[1], faceless = fits[2], nan_point = fits[3];
  optimised.status = PointFitStatus::kOptimized;
  outside.status = PointFitStatus::kOutside;
  faceless.face = kInvalidIndex;
  points.push_back(points[0]), fits.push_back(optimised);
  points.push_back(points[1]), fits.push_back(outside);
  points.push_back(points[2]), fits.push_back(faceless);
  points.push_back(Vec3(std::nan(""), 0.0, 0.0)), fits.push_back(nan_point);
  const std::size_t untouched = 4;

  std::vector<PointFit> one = fits, two = fits;
  const std::int64_t moved = PlaceLostPoints(domain, patches, nullptr, points, &one, 8, 1);
  CHECK(PlaceLostPoints(domain, patches, nullptr, points, &two, 8, 2) == moved);
  CHECK(moved == static_cast<std::int64_t>(points.size() - untouched));
  // Sizes that disagree change nothing.
  std::vector<PointFit> short_fits(fits.begin(), fits.begin() + 3);
  CHECK(PlaceLostPoints(domain, patches, nullptr, points, &short_fits, 8, 1) == 0);
  CHECK(short_fits[0].uv == fits[0].uv);

  int beyond = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    INFO("point " << i);
    CHECK(one[i].face == two[i].face);
    CHECK(one[i].uv == two[i].uv);
    if (i >= points.size() - untouched) {
      CHECK(one[i].face == fits[i].face);
      CHECK(one[i].uv == fits[i].uv);
      continue;
    }
    SurfacePoint before, after;
    REQUIRE(EvaluateSurface(domain, patches, nullptr, fits[i].face, fits[i].uv, &before));
    REQUIRE(EvaluateSurface(domain, patches, nullptr, one[i].face, one[i].uv, &after));
    const double d = glm::length(after.position - points[i]);
    const double reference = tree.Query(points[i]).distance;
    // The tessellation's vertices lie on the surface and its chords within about 3e-5 of it
    // (faces of unit size, 64 segments): the closest point found must agree to that.
    CHECK(std::abs(d - reference) <= 1e-4);
    CHECK(d < glm::length(before.position - points[i]));
    CHECK(one[i].status == PointFitStatus::kNotConverged);
    beyond += reference > 0.1;
  }
  // Points well past the boundary, whose closest point is on it (where Gauss-Newton alone
  // stopped up to 9e-4 short).
  CHECK(beyond >= 6);
}

TEST_CASE("fit: ClosestPointOnSurface reaches a closest point on the boundary") {
  // Points beyond the built-in grid's boundary (4 x 3 quads, open), started at the parameter
  // below them on their own face: the distance returned agrees with a level-64 tessellation's
  // exact one (its chords lie within about 3e-5 of the surface), and the parameter written is
  // where the surface is that far. Gauss-Newton alone halves the steps that leave the surface
  // and stopped short by up to 9e-4 on these.
  ControlSurface surface;
  TriangleDistanceTree tree;
  GridAndReference(&surface, &tree);
  const ManifoldDomain& domain = *surface.domain;
  const LocalPatch* patches = surface.patches.data();
  const MeshTopology& topo = domain.topology();
  int tested = 0;
  for (Index f = 0; f < domain.num_faces(); ++f) {
    for (int e = 0; e < 4; ++e) {
      if (topo.twin(topo.face_offset(f) + e) != kInvalidIndex) continue;
      for (double t : {0.2, 0.5, 0.85}) {
        // Outward along the surface across the edge, and off it along the normal.
        const Vec2 uv = CornerToFace(e, Vec2(t, 0.0));
        SurfacePoint sp, ahead;
        REQUIRE(EvaluateSurface(domain, patches, nullptr, f, uv, &sp));
        REQUIRE(EvaluateSurface(domain, patches, nullptr, f, CornerToFace(e, Vec2(t + 1e-4, 0.0)),
                                &ahead));
        const Vec3 out = glm::normalize(glm::cross(ahead.position - sp.position, sp.normal));
        const Vec3 p = sp.position + 0.3 * out + 0.05 * sp.normal;
        Index face = f;
        Vec2 start = CornerToFace(e, Vec2(t, 0.3));
        const double d = ClosestPointOnSurface(domain, patches, nullptr, p, &face, &start);
        const double reference = tree.Query(p).distance;
        INFO("face " << f << " edge " << e << " t " << t);
        CHECK(std::abs(d - reference) <= 1e-4);
        SurfacePoint at;
        REQUIRE(EvaluateSurface(domain, patches, nullptr, face, start, &at));
        CHECK(glm::length(at.position - p) == Approx(d).margin(1e-12));
        ++tested;
      }
    }
  }
  CHECK(tested >= 30);
}

TEST_CASE("fit: a control-mesh target equal to the full split keeps every triangle") {
  // A closed octahedron of 8 triangles: the full split has V + E + F = 6 + 12 + 8 = 26 quad
  // vertices. Asking for exactly that (or more, which is refused) must not simplify at all
  // (the simplification method; the remesh below).
  PolygonMesh mesh;
  mesh.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const int faces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                           {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (const auto& f : faces) mesh.AddFace({f[0], f[1], f[2]});
  ControlMeshOptions options;
  options.method = ControlMeshMethod::kSimplify;
  options.target_vertices = 26;
  PolygonMesh control;
  const Status s = BuildControlMesh(mesh, options, &control);
  INFO(s.message());
  REQUIRE(s.ok());
  CHECK(control.num_vertices() == 26);
  CHECK(control.num_faces() == 24);
  options.target_vertices = 27;
  CHECK_FALSE(BuildControlMesh(mesh, options, &control).ok());
  // Character fitting lowers a larger target to the full split instead (counted after dropping
  // degenerate triangles, as the control mesh is).
  options.clamp_to_full_split = true;
  options.target_vertices = 1000;
  REQUIRE(BuildControlMesh(mesh, options, &control).ok());
  CHECK(control.num_vertices() == 26);
  // The remesh of so small a mesh: a valid all-quad mesh near the clamped target, with every
  // vertex on the octahedron.
  options.method = ControlMeshMethod::kRemesh;
  ControlMeshInfo info;
  REQUIRE(BuildControlMesh(mesh, options, &control, &info).ok());
  CHECK(info.method == "remesh");
  CHECK(ValidatePolygonMesh(control).ok());
  CHECK(std::abs(control.num_vertices() - 26) <= 6);
  CHECK(control.face_vertices.size() == 4u * static_cast<std::size_t>(control.num_faces()));
  for (const Vec3& p : control.positions) {
    CHECK(std::abs(p.x) + std::abs(p.y) + std::abs(p.z) == Approx(1.0));
  }
}

TEST_CASE("fit: place_control_vertices moves the built control mesh's vertices") {
  // The bumpy sphere's control mesh lies on the bumps; a hook that puts every control vertex
  // on the unit sphere is what the domain surface is built from. A hook that changes the
  // faces is refused; a given control mesh is used as it is, without the hook.
  const PolygonMesh dense = BumpySphereMesh(60, 30, 0.05);
  FitInput input;
  input.points = dense.positions;
  input.mesh = &dense;
  FitOptions options;
  options.control_vertices = 60;
  options.control_fit_iterations = 0;  // the control-vertex fit would move them again
  int calls = 0;
  options.place_control_vertices = [&](PolygonMesh* control) {
    ++calls;
    for (Vec3& x : control->positions) x = glm::normalize(x);
  };
  FittedSurface fitted;
  FitReport report;
  REQUIRE(FitSurface(input, options, &fitted, &report).ok());
  CHECK(calls == 1);
  for (const Vec3& x : fitted.control_mesh.positions) CHECK(glm::length(x) == Approx(1.0));
  for (const Vec3& x : fitted.surface.control.positions) CHECK(glm::length(x) == Approx(1.0));
  FitInput given = input;
  given.control = &fitted.control_mesh;
  FittedSurface again;
  REQUIRE(FitSurface(given, options, &again, &report).ok());
  CHECK(calls == 1);
  options.place_control_vertices = [](PolygonMesh* control) { control->AddFace({0, 1, 2}); };
  const Status s = FitSurface(input, options, &again, &report);
  CHECK(s.code() == StatusCode::kInternal);
  CHECK(s.message().find("changed the faces") != std::string::npos);
}

TEST_CASE("fit: the control fit's regularisation follows the data's noise") {
  // An exact tessellation (noise over spacing 0.0016: the quadric's truncation) slides its
  // control vertices freely over 6 rounds; the same sphere with uniform noise of +-5 % of its
  // spacing along the radius (estimated 0.026, above the noisy ratio of 0.01) is regularised
  // in full over 2; a noisy ratio of 0 always regularises.
  const PolygonMesh exact = BumpySphereMesh(60, 30, 0.05);
  PolygonMesh noisy = exact;
  std::uint64_t state = 7;
  for (Vec3& p : noisy.positions) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    const double u = static_cast<double>(state >> 11) / static_cast<double>(1ull << 53) - 0.5;
    p *= 1.0 + 0.1 * 0.1 * u;  // the spacing is about 0.1: +-0.005 along the radius
  }
  FitOptions options;
  options.control_vertices = 60;
  options.displacement.adaptive.max_levels = 1;
  std::vector<Vec3> control;  // the last fit's control positions
  auto fit = [&](const PolygonMesh& mesh) {
    FitInput input;
    input.points = mesh.positions;
    input.mesh = &mesh;
    FittedSurface fitted;
    FitReport report;
    const Status s = FitSurface(input, options, &fitted, &report);
    INFO(s.message());
    REQUIRE(s.ok());
    control = fitted.control_mesh.positions;
    return report;
  };
  const FitReport clean = fit(exact);
  const std::vector<Vec3> slid = control;
  INFO("noise over spacing: exact " << clean.noise_ratio);
  CHECK(clean.noise_ratio < options.control_fit_clean_ratio);
  CHECK(clean.control_fit_regularisation == 0.0);
  CHECK(clean.control_fit_rounds == options.control_fit_clean_iterations);
  const FitReport rough = fit(noisy);
  INFO("noisy " << rough.noise_ratio);
  CHECK(rough.noise_ratio > options.control_fit_noisy_ratio);
  CHECK(rough.control_fit_regularisation == 1.0);
  CHECK(rough.control_fit_rounds == options.control_fit_iterations);
  options.control_fit_noisy_ratio = 0.0;
  const FitReport fixed = fit(exact);
  CHECK(fixed.noise_ratio == 0.0);
  CHECK(fixed.control_fit_regularisation == 1.0);
  CHECK(fixed.control_fit_rounds == options.control_fit_iterations);
  // The same control mesh, fitted with and without the regularisation: the settings reached
  // the rounds (the free slide moves the vertices elsewhere).
  REQUIRE(control.size() == slid.size());
  double moved = 0.0;
  for (std::size_t i = 0; i < slid.size(); ++i)
    moved = std::max(moved, glm::length(slid[i] - control[i]));
  INFO("largest difference of a control vertex: " << moved);
  CHECK(moved > 1e-3);
}

TEST_CASE("fit: .dsurf round trip is bit-exact and threads do not change the bytes") {
  const PolygonMesh dense = BumpySphereMesh(60, 30, 0.05);
  FitInput input;
  input.points = dense.positions;
  input.mesh = &dense;
  FitOptions options;
  options.control_vertices = 60;
  std::string bytes[2];
  for (int t = 0; t < 2; ++t) {
    options.threads = t + 1;
    FittedSurface fitted;
    FitReport report;
    REQUIRE(FitSurface(input, options, &fitted, &report).ok());
    bytes[t] = SerializeDsurf(*fitted.surface.domain, fitted.surface.control.positions.data(),
                              fitted.displacement.get(), report.points);
    // Parse and write again: same bytes; same surface.
    DisplacedSurface loaded;
    REQUIRE(ParseDsurf(bytes[t], "memory", &loaded).ok());
    CHECK(loaded.data_points == report.points);
    CHECK(SerializeDsurf(*loaded.domain, loaded.rest_positions.data(), loaded.displacement.get(),
                         loaded.data_points) == bytes[t]);
    std::vector<LocalPatch> patches(loaded.rest_positions.size());
    loaded.domain->FitPatches(loaded.rest_positions.data(), patches.data());
    SurfacePoint a, b;
    REQUIRE(EvaluateSurface(*fitted.surface.domain, fitted.surface.patches.data(),
                            fitted.displacement.get(), 3, Vec2(0.3, 0.7), &a));
    REQUIRE(EvaluateSurface(*loaded.domain, patches.data(), loaded.displacement.get(), 3,
                            Vec2(0.3, 0.7), &b));
    CHECK(a.position == b.position);
  }
  CHECK(bytes[0] == bytes[1]);
  // Damaged files are refused with a message, never crash.
  DisplacedSurface out;
  Status s = ParseDsurf(bytes[0].substr(0, bytes[0].size() / 2), "half.dsurf", &out);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("half.dsurf") != std::string::npos);
  std::string flipped = bytes[0];
  flipped[100] = static_cast<char>(flipped[100] ^ 0x5a);
  CHECK_FALSE(ParseDsurf(flipped, "flipped.dsurf", &out).ok());
  CHECK_FALSE(ParseDsurf("not a dsurf file at all", "text.dsurf", &out).ok());
  for (std::size_t cut = 0; cut < 64; ++cut)
    CHECK_FALSE(ParseDsurf(bytes[0].substr(0, cut), "cut", &out).ok());
  CHECK(ReadDsurf("/nonexistent/dir/x.dsurf", &out).code() == StatusCode::kIoError);
}

TEST_CASE("fit: a point's weight reaches its own target through the held-out split") {
  // One fitted point weighs 1e4: the displacement levels pass through it (the others hold
  // the surface near it), which only works if its weight follows it past the held-out points.
  const PolygonMesh dense = BumpySphereMesh(20, 10, 0.05);
  FitOptions options;
  options.holdout = 0.3;
  options.control_vertices = 40;
  options.threads = 2;
  // The heavy point: an input point after several held-out ones, and its place among the
  // fitted points.
  std::size_t heavy = 0, held_before = 0, fitted_index = 0;
  for (std::size_t i = 0, k = 0; i < dense.positions.size(); ++i) {
    if (IsHeldOut(i, options.holdout, options.holdout_seed)) {
      ++held_before;
      continue;
    }
    if (held_before >= 5 && i >= 60) {
      heavy = i, fitted_index = k;
      break;
    }
    ++k;
  }
  REQUIRE(heavy > 0);
  auto error_at_heavy = [&](double weight) {
    FitInput input;
    input.points = dense.positions;
    input.mesh = &dense;
    input.weights.assign(dense.positions.size(), 1.0);
    input.weights[heavy] = weight;
    FittedSurface fitted;
    FitReport report;
    REQUIRE(FitSurface(input, options, &fitted, &report).ok());
    const PointFit& f = fitted.point_fits[fitted_index];
    SurfacePoint sp;
    REQUIRE(EvaluateSurface(*fitted.surface.domain, fitted.surface.patches.data(),
                            fitted.displacement.get(), f.face, f.uv, &sp));
    return glm::length(sp.position - dense.positions[heavy]);
  };
  const double light = error_at_heavy(1.0), weighted = error_at_heavy(1e4);
  INFO("input point " << heavy << " (fitted point " << fitted_index << "): |D - p| " << light
                      << " at weight 1, " << weighted << " at weight 1e4");
  CHECK(weighted < 0.2 * light);
}

TEST_CASE("fit: bad inputs give clear errors") {
  FittedSurface fitted;
  FitReport report;
  FitOptions options;
  FitInput empty;
  Status s = FitSurface(empty, options, &fitted, &report);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("no data points") != std::string::npos);

  const PolygonMesh dense = BumpySphereMesh(20, 10, 0.05);
  FitInput nan;
  nan.points = dense.positions;
  nan.points[5].y = std::nan("");
  nan.mesh = &dense;
  s = FitSurface(nan, options, &fitted, &report);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("point 5") != std::string::npos);

  FitInput weights;
  weights.points = dense.positions;
  weights.mesh = &dense;
  weights.weights.assign(dense.positions.size() - 1, 1.0);
  s = FitSurface(weights, options, &fitted, &report);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("point weights for") != std::string::npos);
  weights.weights.assign(dense.positions.size(), 1.0);
  weights.weights[7] = 0.0;
  s = FitSurface(weights, options, &fitted, &report);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("point 7 has a weight") != std::string::npos);

  FitInput bad_check;
  bad_check.points = dense.positions;
  bad_check.mesh = &dense;
  bad_check.check_points.assign(4, Vec3(0.0));
  bad_check.check_points[3].z = std::numeric_limits<double>::infinity();
  s = FitSurface(bad_check, options, &fitted, &report);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("check point 3 is not finite") != std::string::npos);
  bad_check.check_points[3].z = 0.0;
  bad_check.check_normals.assign(3, Vec3(0.0, 0.0, 1.0));
  s = FitSurface(bad_check, options, &fitted, &report);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("3 check normals for 4 check points") != std::string::npos);
  bad_check.check_normals.assign(4, Vec3(0.0, 0.0, 1.0));
  bad_check.check_normals[1].x = std::numeric_limits<double>::quiet_NaN();
  s = FitSurface(bad_check, options, &fitted, &report);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("check normal 1 is not finite") != std::string::npos);
  bad_check.check_normals[1] = Vec3(0.0, 0.0, 0.1);  // neither unit nor zero
  s = FitSurface(bad_check, options, &fitted, &report);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("check normal 1 is neither unit nor zero") != std::string::npos);
  bad_check.check_normals[1] = Vec3(0.0);  // zero: no normal there, taken
  FitOptions negative = options;
  negative.displacement.adaptive.check_shading_tolerance = -0.1;
  s = FitSurface(bad_check, negative, &fitted, &report);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("shading tolerance") != std::string::npos);

  FitInput too_many;
  too_many.points = dense.positions;
  too_many.mesh = &dense;
  options.control_vertices = 100000;
  s = FitSurface(too_many, options, &fitted, &report);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("--control-vertices") != std::string::npos);

  FitInput cloud;
  cloud.points = dense.positions;
  s = FitSurface(cloud, FitOptions(), &fitted, &report);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("--control-mesh") != std::string::npos);

  PolygonMesh m;
  Index dropped = 0;
  s = ReadFitInput("/nonexistent/bunny.obj", &m, &dropped);
  CHECK(s.code() == StatusCode::kIoError);
  CHECK(s.message().find("/nonexistent/bunny.obj") != std::string::npos);
  s = ReadFitInput("scan.xyz", &m, &dropped);
  CHECK(s.code() == StatusCode::kUnsupported);
}

TEST_CASE("fit: a far root of the common-displacement solve is not taken", "[heavy]") {
  // With 600 control vertices and at least 6 coarse edges per hole the bunny's control mesh
  // let one point's solve converge to delta = 6 times the scan's size (the normal line of a
  // distant part of the surface through the point); the displacement levels fitted to it
  // spiked the surface: E1 max 0.154, Hausdorff 126% of the diagonal. Such a root is now
  // refused (point_fit.cpp) and the point counts as not converged.
  PolygonMesh mesh;
  Index dropped = 0;
  if (!ReadSharedBunny(&mesh, &dropped)) return;
  FitInput input;
  input.points = mesh.positions;
  input.mesh = &mesh;
  FitOptions options;
  options.control_vertices = 600;
  options.remesh.sizing.loop_segments = 6;
  FittedSurface fitted;
  FitReport report;
  REQUIRE(FitSurface(input, options, &fitted, &report).ok());
  INFO("E1 max " << report.error.max << ", Hausdorff " << report.error.hausdorff_percent_diagonal
                 << "%");
  double largest = 0.0;
  for (const PointFit& f : fitted.point_fits) {
    if (f.status == PointFitStatus::kOptimized) largest = std::max(largest, std::abs(f.delta));
  }
  CHECK(largest <= 0.1 * report.scale);
  CHECK(report.error.max <= 0.02);
  CHECK(report.error.hausdorff_percent_diagonal <= 3.0);
}

TEST_CASE("fit: the Stanford bunny with 540 control vertices", "[heavy]") {
  PolygonMesh mesh;
  Index dropped = 0;
  if (!ReadSharedBunny(&mesh, &dropped)) return;
  CHECK(dropped == 1113);
  CHECK(mesh.num_vertices() == 34834);
  FitInput input;
  input.points = mesh.positions;
  input.mesh = &mesh;
  input.points_dropped = dropped;
  FitOptions options;
  FittedSurface fitted;
  FitReport report;
  REQUIRE(FitSurface(input, options, &fitted, &report).ok());
  INFO("E1 " << report.error.mean << " held out " << report.error.holdout_mean << ", "
             << report.coefficients << " coefficients");
  CHECK(std::abs(report.control_vertices - 540) <= 10);
  // The remeshed control mesh with adaptive displacement levels (docs/fitting.md): E1 8.7e-5 and
  // held out 2.59e-4 with 2.7 coefficients per point, where the simplified control mesh with
  // dense per-chart lattices took 14.8 per point for E1 1.45e-4 and held out 3.29e-4. The
  // held-out error stays near the scan's noise (docs/fitting.md), so the ratio is loose, and it
  // grows as E1 falls (3.31 since the boundary cover lowered E1 to 7.6e-5; 2.5e-4 held out).
  CHECK(report.error.mean <= 1.0e-4);
  CHECK(report.error.holdout_mean <= 2.9e-4);
  CHECK(report.error.holdout_mean <= 3.5 * report.error.mean);
  CHECK(report.coefficients <= 3 * report.points);
  CHECK(report.coefficients_per_point ==
        Approx(static_cast<double>(report.coefficients) / static_cast<double>(report.points)));
  // The stopping rule or the budget, not the level cap, ended the fit.
  CHECK(report.displacement_fit.levels >= 4);
  CHECK(report.displacement_fit.stopped_by != "max levels");
  // The remeshed control mesh (docs/fitting.md, "Control mesh").
  CHECK(report.control_mesh.method == "remesh");
  CHECK(report.control_mesh.quality.valence4_share >= 0.8);
  CHECK(report.control_mesh.quality.boundary_loops == 5);
  CHECK(report.control_mesh.quality.components == 1);
  CHECK(report.error.unoptimized_mean > 5.0 * report.error.mean);
  CHECK(report.points_outside < 100);
  CHECK(report.control_fit_rounds == 2);
  // Independently: the fitted points against the level-32 tessellation (exact
  // point-to-triangle distances) are within the reported E1 on average. (Level 16 adds about
  // 2e-5 of chord error, a fifth of E1 now; bench_fit prints both.)
  TessellationPattern pattern;
  REQUIRE(TessellationPattern::Build(fitted.surface.domain->topology(), 32, &pattern).ok());
  std::vector<Vec3> x(pattern.samples.size());
  REQUIRE(EvaluateSamples(*fitted.surface.domain, fitted.surface.patches.data(),
                          fitted.displacement.get(), pattern.samples.data(), x.size(), x.data(),
                          nullptr));
  TriangleDistanceTree tree;
  tree.Build(x, pattern.triangles);
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < input.points.size(); ++i) {
    if (IsHeldOut(i, options.holdout, options.holdout_seed)) continue;
    sum += tree.Query(input.points[i]).distance / report.scale, ++n;
  }
  INFO("level-32 tessellation: mean " << sum / static_cast<double>(n));
  CHECK(sum / static_cast<double>(n) <= report.error.mean);
  // The boundary cover (docs/fitting.md, "Covering the data's boundary"): the scan's hole rims
  // ran up to 1.48e-2 beyond the domain surface's boundary curve, and with them E1's largest
  // (6.99e-3 without the cover, the goal 5e-3). Independently: every boundary vertex of
  // the scan, held-out ones too, lies within 6e-3 of the level-32 tessellation (5.2e-3 measured,
  // at a held-out rim vertex; 1.48e-2 without the cover).
  CHECK(report.boundary_points_beyond > 0);
  CHECK(report.boundary_vertices_moved > 0);
  CHECK(report.boundary_largest_excess > 5e-3);
  CHECK(report.error.max <= 5e-3);
  const std::vector<std::pair<Vec3, Vec3>> rim = BoundaryEdges(mesh);
  CHECK(rim.size() > 100);
  double rim_max = 0.0;
  for (const auto& e : rim)
    rim_max = std::max(rim_max, tree.Query(e.first).distance / report.scale);
  INFO("scan boundary vertices to the level-32 tessellation: max " << rim_max);
  CHECK(rim_max <= 6e-3);
}

TEST_CASE("fit: the smooth torus meets issue 15's domain and full-surface goals", "[heavy]") {
  // The built-in torus's surface tessellated at level 12 (6,912 exact points) fitted with 200
  // control vertices; distances in the unit where the largest side is 1, the fit tessellated
  // at level 24, both directions (bench_fit --rows torus). The input is exactly symmetric, so
  // its control mesh depends on how rounding breaks ties: the goals are judged on the median
  // of nine draws, the exact input and eight moved by at most 1e-12 (docs/fitting.md,
  // "Measured: the torus"). Goals: domain surface mean <= 5e-4 and max <= 5e-3, full surface
  // max <= 2e-3. Measured: 4.86e-4, 3.69e-3 and 8.8e-4.
  PolygonMesh control;
  REQUIRE(MakeBuiltinMesh("torus", &control).ok());
  ControlSurface cs;
  REQUIRE(BuildControlSurface(control, DomainOptions(), &cs).ok());
  TessellationPattern pattern;
  REQUIRE(TessellationPattern::Build(cs.domain->topology(), 12, &pattern).ok());
  std::vector<double> domain_mean, domain_max, full_max;
  for (unsigned seed = 0; seed <= 8; ++seed) {
    PolygonMesh mesh;
    mesh.positions.resize(pattern.samples.size());
    EvaluateSamples(*cs.domain, cs.patches.data(), nullptr, pattern.samples.data(),
                    pattern.samples.size(), mesh.positions.data(), nullptr);
    if (seed > 0) {
      std::mt19937 rng(seed);
      std::uniform_real_distribution<double> u(-1e-12, 1e-12);
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
    options.control_vertices = 200;
    FittedSurface fitted;
    FitReport report;
    REQUIRE(FitSurface(input, options, &fitted, &report).ok());
    CHECK(report.control_fit_regularisation == 0.0);  // an exact tessellation: clean
    TriangleDistanceTree data_tree;
    data_tree.Build(mesh.positions, TriangulateFan(mesh));
    TessellationPattern fine;
    REQUIRE(TessellationPattern::Build(fitted.surface.domain->topology(), 24, &fine).ok());
    for (int full = 0; full < 2; ++full) {
      TruncatedDisplacement none(fitted.displacement.get(), 0);
      const Displacement* disp =
          full ? static_cast<const Displacement*>(fitted.displacement.get()) : &none;
      std::vector<Vec3> x(fine.samples.size());
      EvaluateSamples(*fitted.surface.domain, fitted.surface.patches.data(), disp,
                      fine.samples.data(), x.size(), x.data(), nullptr);
      TriangleDistanceTree surface_tree;
      surface_tree.Build(x, fine.triangles);
      double mean[2] = {0.0, 0.0}, max = 0.0;
      for (const Vec3& p : mesh.positions) {
        const double d = surface_tree.Query(p).distance / report.scale;
        mean[0] += d / static_cast<double>(mesh.positions.size());
        max = std::max(max, d);
      }
      for (const Vec3& p : x) {
        const double d = data_tree.Query(p).distance / report.scale;
        mean[1] += d / static_cast<double>(x.size());
        max = std::max(max, d);
      }
      if (full) {
        full_max.push_back(max);
      } else {
        domain_mean.push_back(std::max(mean[0], mean[1]));
        domain_max.push_back(max);
      }
    }
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  INFO("median of nine draws: domain mean " << median(domain_mean) << ", domain max "
                                            << median(domain_max) << ", full max "
                                            << median(full_max));
  CHECK(median(domain_mean) <= 5e-4);
  CHECK(median(domain_max) <= 5e-3);
  CHECK(median(full_max) <= 2e-3);
}

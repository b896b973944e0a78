// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The control-vertex fit: the linear stencil of the domain surface against the evaluator, exact
// recovery of a control mesh from points on its own surface, thread independence, and its use
// in FitSurface (a built control mesh moves towards the data, a given one never moves).
#include "dermis/offline/fit/control_fit.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <random>
#include <vector>

#include "dermis/offline/fit/surface_fit.h"
#include "dermis/offline/fit/surface_projection.h"
#include "dermis/offline/geometry/builtin_meshes.h"
#include "dermis/surface/blend.h"
#include "dermis/surface/chart.h"
#include "dermis/surface/local_patch.h"
#include "dermis/surface/surface_evaluator.h"
#include "test_meshes.h"

using namespace dermis;
using namespace dermis::test;

namespace {

// Face coordinates that exercise the one-chart corners, the edges and the blend zones.
std::vector<Vec2> TestCoordinates() {
  std::vector<Vec2> uv = {{0.0, 0.0},     {1.0, 0.0}, {1.0, 1.0},  {0.0, 1.0},   {0.5, 0.5},
                          {0.005, 0.003}, {0.5, 0.0}, {0.0, 0.37}, {0.999, 0.5}, {0.25, 0.75}};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 20; ++i) uv.emplace_back(u(rng), u(rng));
  return uv;
}

// Points on the domain surface of `positions` at a grid of face coordinates, with their exact
// parameters as optimised fits.
void SampleDomain(const ControlSurface& cs, const std::vector<Vec3>& positions, int n,
                  std::vector<Vec3>* points, std::vector<PointFit>* fits) {
  std::vector<LocalPatch> patches(positions.size());
  cs.domain->FitPatches(positions.data(), patches.data());
  for (Index f = 0; f < cs.domain->num_faces(); ++f) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        PointFit pf;
        pf.status = PointFitStatus::kOptimized;
        pf.face = f;
        pf.uv = Vec2((i + 0.5) / n, (j + 0.5) / n);
        SurfacePoint sp;
        REQUIRE(EvaluateSurface(*cs.domain, patches.data(), nullptr, f, pf.uv, &sp));
        points->push_back(sp.position);
        fits->push_back(pf);
      }
    }
  }
}

double MaxDistance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double d = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, glm::length(a[i] - b[i]));
  return d;
}

// A perturbed built-in control mesh, its surface, and points on that surface at a grid of
// face coordinates (SampleDomain, n = 8) with their exact parameters.
struct SampledSurface {
  ControlSurface cs;
  std::vector<Vec3> truth;
  std::vector<Vec3> points;
  std::vector<PointFit> fits;
};

SampledSurface SampleBuiltin(const char* name) {
  PolygonMesh mesh = Builtin(name);
  Perturb(&mesh, 0.05, 3);
  SampledSurface s;
  s.cs = Build(mesh);
  s.truth = s.cs.control.positions;
  SampleDomain(s.cs, s.truth, 8, &s.points, &s.fits);
  return s;
}

}  // namespace

TEST_CASE("control fit: the stencil reproduces the domain surface") {
  for (const char* name : {"cube", "house", "prism7", "torus", "grid", "octahedron"}) {
    PolygonMesh mesh = Builtin(name);
    Perturb(&mesh, 0.05, 11);
    const ControlSurface cs = Build(mesh);
    const ManifoldDomain& domain = *cs.domain;
    const std::vector<Vec3>& x = cs.control.positions;
    std::vector<std::pair<Index, double>> st;
    double worst = 0.0;
    for (Index f = 0; f < domain.num_faces(); ++f) {
      for (Vec2 uv : TestCoordinates()) {
        SurfacePoint sp;
        REQUIRE(EvaluateSurface(domain, cs.patches.data(), nullptr, f, uv, &sp));
        st.clear();
        REQUIRE(DomainSurfaceStencil(domain, f, uv, &st));
        Vec3 q(0.0);
        double sum = 0.0;
        for (const auto& [v, w] : st) q += w * x[v], sum += w;
        worst = std::max(worst, glm::length(q - sp.position));
        // Affine invariance of the surface: the weights sum to 1.
        CHECK(sum == Approx(1.0).margin(1e-12));
      }
    }
    INFO(name);
    CHECK(worst < 1e-12);
  }
  std::vector<std::pair<Index, double>> st;
  const ControlSurface cs = Build(Builtin("cube"));
  CHECK_FALSE(DomainSurfaceStencil(*cs.domain, -1, Vec2(0.5), &st));
  CHECK_FALSE(DomainSurfaceStencil(*cs.domain, 0, Vec2(1.5, 0.5), &st));
  CHECK(st.empty());
}

TEST_CASE("control fit: recovers the control mesh whose surface was sampled") {
  for (const char* name : {"house", "prism7", "grid"}) {
    const SampledSurface sampled = SampleBuiltin(name);
    const ControlSurface& cs = sampled.cs;
    const std::vector<Vec3>& truth = sampled.truth;
    const std::vector<Vec3>& points = sampled.points;
    const std::vector<PointFit>& fits = sampled.fits;
    // Start away from the truth; each damped step is a contraction towards it.
    std::vector<Vec3> x = truth;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.05, 0.05);
    for (Vec3& p : x) p += Vec3(u(rng), u(rng), u(rng));
    const double start = MaxDistance(x, truth);
    // The point distance at fixed parameters: a least-squares problem whose minimum is the truth.
    ControlFitOptions options;
    options.threads = 1;
    options.tangent_weight = 1.0;
    options.tangent_damping = 0.0;
    REQUIRE(FitControlPositions(*cs.domain, points, fits, options, &x).ok());
    const double one_step = MaxDistance(x, truth);
    for (int it = 0; it < 20; ++it) {
      REQUIRE(FitControlPositions(*cs.domain, points, fits, options, &x).ok());
    }
    INFO(name << ": start " << start << ", after one step " << one_step << ", after 21 "
              << MaxDistance(x, truth));
    CHECK(one_step < 0.1 * start);
    CHECK(MaxDistance(x, truth) < 1e-9);
  }
}

TEST_CASE("control fit: with parameters off along the surface the tangent weight keeps its shape") {
  // Points on the domain surface of the truth, each given a parameter moved along the surface
  // (by up to 0.06 of a face): the point distance pulls the surface to put every point at the
  // wrong parameter and bends it off the points; measured across the surface only, the
  // residuals are (to second order) zero and the step leaves the surface on the points.
  for (const char* name : {"prism7", "torus"}) {
    SampledSurface sampled = SampleBuiltin(name);
    const ControlSurface& cs = sampled.cs;
    const std::vector<Vec3>& truth = sampled.truth;
    const std::vector<Vec3>& points = sampled.points;
    std::vector<PointFit>& fits = sampled.fits;
    const std::vector<PointFit> exact = fits;
    std::mt19937 rng(13);
    std::uniform_real_distribution<double> u(-0.06, 0.06);
    for (PointFit& f : fits) f.uv = glm::clamp(f.uv + Vec2(u(rng), u(rng)), Vec2(0.0), Vec2(1.0));
    // The largest distance from the points to the domain surface of x (closest points found
    // from each point's true parameter cell, so the search starts in the right basin).
    auto worst_distance = [&](const std::vector<Vec3>& x) {
      std::vector<LocalPatch> patches(x.size());
      cs.domain->FitPatches(x.data(), patches.data());
      double worst = 0.0;
      for (std::size_t i = 0; i < points.size(); ++i) {
        Index face = exact[i].face;
        Vec2 uv = exact[i].uv;
        worst = std::max(worst, ClosestPointOnSurface(*cs.domain, patches.data(), nullptr,
                                                      points[i], &face, &uv));
      }
      return worst;
    };
    double after[2];
    for (int k = 0; k < 2; ++k) {
      std::vector<Vec3> x = truth;
      ControlFitOptions options;
      options.threads = 1;
      options.tangent_weight = k == 0 ? 1.0 : 0.01;
      options.tangent_damping = 0.0;
      REQUIRE(FitControlPositions(*cs.domain, points, fits, options, &x).ok());
      after[k] = worst_distance(x);
    }
    INFO(name << ": largest distance after one step, point distance " << after[0]
              << ", tangent weight 0.01 " << after[1]);
    CHECK(worst_distance(truth) < 1e-9);
    CHECK(after[1] < 0.25 * after[0]);
  }
}

TEST_CASE("control fit: the assembled objective is minimised, with and without the agreement") {
  // Points on a differently perturbed surface, at fixed parameters. With the robust weights
  // off, the fit minimises, written here with the evaluator (not the stencils it assembles):
  //   E(X) = sum_i r_i^T M_i r_i + w sum_i sum_a psi_a |P_a(z_a; X) - Q_i(X)|^2
  //          + sum_v (X_v - X0_v)^T D_v (X_v - X0_v),
  // r_i = Q_i(X) - p_i, M_i = t I + (1 - t) n_i n_i^T (n_i the domain surface's normal at the
  // starting positions X0), D_v = mt I + (mu - mt) m_v m_v^T (m_v the patch's one-ring normal
  // at X0), mu = max(damping d_v, 0.01 mean d), mt = max(tangent damping d_v, mu) and
  // d_v = sum_i (t + (1 - t) / 3) (the summed stencil weight of v at point i)^2. E is
  // quadratic, so central differences are its exact directional derivatives: zero at the
  // minimiser the fit returns, for the point distance (t = 1, every block a multiple of the
  // identity) and the tangent-weighted residual (t = 0.01, coordinates coupled).
  PolygonMesh mesh = Builtin("prism7");
  Perturb(&mesh, 0.05, 3);
  const ControlSurface cs = Build(mesh);
  const ManifoldDomain& domain = *cs.domain;
  const Index nv = domain.num_vertices();
  for (Index v = 0; v < nv; ++v) REQUIRE_FALSE(domain.topology().is_boundary_vertex(v));
  std::vector<Vec3> other = cs.control.positions;
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-0.08, 0.08);
  for (Vec3& p : other) p += Vec3(u(rng), u(rng), u(rng));
  std::vector<Vec3> points;
  std::vector<PointFit> fits;
  SampleDomain(cs, other, 5, &points, &fits);
  const std::vector<Vec3> x0 = cs.control.positions;
  // The domain surface's normals at the points and the one-ring normals, at X0.
  std::vector<LocalPatch> patches0(x0.size());
  domain.FitPatches(x0.data(), patches0.data());
  std::vector<Vec3> normals;
  for (const PointFit& f : fits) {
    SurfacePoint sp;
    REQUIRE(EvaluateSurface(domain, patches0.data(), nullptr, f.face, f.uv, &sp));
    normals.push_back(sp.normal);
  }
  // Each vertex's summed squared stencil weight.
  std::vector<double> stencil2(static_cast<std::size_t>(nv), 0.0);
  for (const PointFit& f : fits) {
    std::vector<std::pair<Index, double>> st;
    REQUIRE(DomainSurfaceStencil(domain, f.face, f.uv, &st));
    std::map<Index, double> row;
    for (const auto& [v, w] : st) row[v] += w;
    for (const auto& [v, w] : row) stencil2[static_cast<std::size_t>(v)] += w * w;
  }
  // The agreement sum (unweighted) at positions x.
  const double lb = domain.options().blend_lb;
  auto agreement = [&](const std::vector<Vec3>& x) {
    std::vector<LocalPatch> patches(x.size());
    domain.FitPatches(x.data(), patches.data());
    double sum = 0.0;
    for (const PointFit& f : fits) {
      SurfacePoint sp;
      REQUIRE(EvaluateSurface(domain, patches.data(), nullptr, f.face, f.uv, &sp));
      for (int a = 0; a < 4; ++a) {
        const Vec2 cd = FaceToCorner(a, f.uv);
        if (cd.x >= 1.0 - lb || cd.y >= 1.0 - lb) continue;
        const double psi = CornerWeight(domain.options().blend_type, lb, cd);
        PatchJet jet;
        EvaluatePatch(patches[domain.topology().face_vertex(f.face, a)],
                      domain.FaceToChart(f.face, a, f.uv), &jet);
        sum += psi * glm::dot(jet.p - sp.position, jet.p - sp.position);
      }
    }
    return sum;
  };
  struct Case {
    double t, tangent_damping, w;
  };
  double disagreement[2] = {0.0, 0.0};
  for (const Case& c :
       {Case{1.0, 0.0, 0.0}, Case{1.0, 0.0, 10.0}, Case{0.01, 0.3, 0.0}, Case{0.01, 0.3, 1.0}}) {
    ControlFitOptions options;
    options.threads = 2;
    options.robust_cutoff = 0.0;
    options.tangent_weight = c.t;
    options.tangent_damping = c.tangent_damping;
    options.patch_agreement = c.w;
    double mean_d = 0.0;
    std::vector<double> d(stencil2.size());
    for (std::size_t v = 0; v < d.size(); ++v) {
      d[v] = (c.t + (1.0 - c.t) / 3.0) * stencil2[v];
      mean_d += d[v] / static_cast<double>(nv);
    }
    auto energy = [&](const std::vector<Vec3>& x) {
      std::vector<LocalPatch> patches(x.size());
      domain.FitPatches(x.data(), patches.data());
      double e = c.w > 0.0 ? c.w * agreement(x) : 0.0;
      for (std::size_t i = 0; i < fits.size(); ++i) {
        SurfacePoint sp;
        REQUIRE(EvaluateSurface(domain, patches.data(), nullptr, fits[i].face, fits[i].uv, &sp));
        const Vec3 r = sp.position - points[i];
        const double rn = glm::dot(r, normals[i]);
        e += c.t * glm::dot(r, r) + (1.0 - c.t) * rn * rn;
      }
      for (Index v = 0; v < nv; ++v) {
        const auto k = static_cast<std::size_t>(v);
        const double mu = std::max(options.damping * d[k], 0.01 * mean_d);
        const double mt = std::max(options.tangent_damping * d[k], mu);
        const Vec3 dx = x[v] - x0[v];
        const double dn = glm::dot(dx, patches0[k].fallback_normal);
        e += mt * glm::dot(dx, dx) + (mu - mt) * dn * dn;
      }
      return e;
    };
    std::vector<Vec3> x = x0;
    REQUIRE(FitControlPositions(domain, points, fits, options, &x).ok());
    if (c.t == 1.0) disagreement[c.w > 0.0 ? 1 : 0] = agreement(x);
    // Directional derivatives of E at the fit's result along random directions, against the
    // same at the start (where the data pull is large).
    std::mt19937 dir_rng(40);
    std::normal_distribution<double> g(0.0, 1.0);
    const double eps = 1e-3;
    for (int trial = 0; trial < 4; ++trial) {
      std::vector<Vec3> dir(x.size());
      for (Vec3& v : dir) v = Vec3(g(dir_rng), g(dir_rng), g(dir_rng));
      auto derivative = [&](const std::vector<Vec3>& at) {
        std::vector<Vec3> plus = at, minus = at;
        for (std::size_t i = 0; i < at.size(); ++i) {
          plus[i] += eps * dir[i], minus[i] -= eps * dir[i];
        }
        return (energy(plus) - energy(minus)) / (2.0 * eps);
      };
      const double at_start = derivative(x0);
      const double at_fit = derivative(x);
      INFO("t " << c.t << ", tangent damping " << c.tangent_damping << ", agreement " << c.w
                << ": derivative at the start " << at_start << ", at the fit " << at_fit);
      CHECK(std::abs(at_start) > 1e-3);
      CHECK(std::abs(at_fit) < 1e-6 * std::abs(at_start) + 1e-9);
    }
  }
  INFO("patch disagreement without the term " << disagreement[0] << ", with weight 10 "
                                              << disagreement[1]);
  CHECK(disagreement[0] > 0.0);
  CHECK(disagreement[1] < 0.5 * disagreement[0]);
}

TEST_CASE("control fit: the same result whatever the thread count, and bad sizes refused") {
  PolygonMesh mesh = Builtin("house");
  Perturb(&mesh, 0.05, 9);
  const ControlSurface cs = Build(mesh);
  std::vector<Vec3> points;
  std::vector<PointFit> fits;
  SampleDomain(cs, cs.control.positions, 6, &points, &fits);
  // Noisy data so the robust weights take part.
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  for (Vec3& p : points) p += Vec3(u(rng), u(rng), u(rng));
  points[3] += Vec3(0.5, 0.0, 0.0);  // an outlier
  std::vector<Vec3> results[3];
  for (int threads : {1, 2, 3}) {
    std::vector<Vec3> x = cs.control.positions;
    ControlFitOptions options;
    options.threads = threads;
    REQUIRE(FitControlPositions(*cs.domain, points, fits, options, &x).ok());
    results[threads - 1] = x;
  }
  for (int k = 1; k < 3; ++k) {
    REQUIRE(results[k].size() == results[0].size());
    CHECK(std::memcmp(results[k].data(), results[0].data(), results[0].size() * sizeof(Vec3)) == 0);
  }
  std::vector<Vec3> x(2);
  const Status s = FitControlPositions(*cs.domain, points, fits, ControlFitOptions{}, &x);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("sizes") != std::string::npos);
}

TEST_CASE("control fit: a built control mesh moves towards the data, a given one stays") {
  // A dense, finely bumped sphere-like mesh: a subdivided octahedron pushed onto the sphere.
  PolygonMesh dense = Builtin("octahedron");
  for (int round = 0; round < 4; ++round) {
    PolygonMesh next;
    next.source_name = "dense sphere";
    next.positions = dense.positions;
    std::map<std::pair<Index, Index>, Index> mid;
    auto midpoint = [&](Index a, Index b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      next.positions.push_back(0.5 * (dense.positions[a] + dense.positions[b]));
      return mid[key] = next.num_vertices() - 1;
    };
    for (Index f = 0; f < dense.num_faces(); ++f) {
      const Index* v = dense.face_vertices.data() + dense.face_offsets[f];
      const Index a = midpoint(v[0], v[1]), b = midpoint(v[1], v[2]), c = midpoint(v[2], v[0]);
      next.AddFace({v[0], a, c});
      next.AddFace({a, v[1], b});
      next.AddFace({c, b, v[2]});
      next.AddFace({a, b, c});
    }
    dense = next;
  }
  for (Vec3& p : dense.positions) p /= glm::length(p);
  FitInput input;
  input.points = dense.positions;
  input.mesh = &dense;
  FitOptions options;
  options.control_vertices = 60;
  options.holdout = 0.0;
  options.threads = 2;
  // Mean distance from the data to the domain surface (no displacement) at the fitted
  // parameters.
  auto domain_error = [&](const FittedSurface& f) {
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < f.point_fits.size(); ++i) {
      const PointFit& pf = f.point_fits[i];
      if (pf.status == PointFitStatus::kOutside) continue;
      SurfacePoint sp;
      EvaluateSurface(*f.surface.domain, f.surface.patches.data(), nullptr, pf.face, pf.uv, &sp);
      sum += glm::length(sp.position - input.points[i]), ++n;
    }
    return sum / static_cast<double>(n);
  };
  FittedSurface plain, fitted;
  FitReport report;
  options.control_fit_iterations = 0;
  REQUIRE(FitSurface(input, options, &plain, &report).ok());
  options.control_fit_iterations = 2;
  REQUIRE(FitSurface(input, options, &fitted, &report).ok());
  INFO("domain error without " << domain_error(plain) << ", with " << domain_error(fitted));
  // The remeshed control mesh starts close (its vertices on the sphere, evenly spread); the
  // fit still takes the domain surface's error down by more than 40%.
  CHECK(domain_error(fitted) < 0.6 * domain_error(plain));
  CHECK(fitted.control_mesh.positions == fitted.surface.control.positions);
  // A given control mesh is used as is.
  PolygonMesh given = plain.control_mesh;
  input.control = &given;
  FittedSurface kept;
  REQUIRE(FitSurface(input, options, &kept, &report).ok());
  CHECK(kept.surface.control.positions == given.positions);
}

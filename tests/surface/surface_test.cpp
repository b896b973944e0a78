// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>

#include "dermis/surface/surface_evaluator.h"
#include "support/domains.h"

using namespace dermis;

namespace {

// Meshes covering interior valences 3..16 and boundary creases and corners.
std::vector<std::pair<std::string, PolygonMesh>> TestMeshes(bool perturb) {
  std::vector<std::pair<std::string, PolygonMesh>> out;
  for (int k = 3; k <= 12; ++k)
    out.push_back({"prism" + std::to_string(k), test::Builtin("prism" + std::to_string(k))});
  for (const char* name : {"cube", "torus", "house", "grid", "octahedron"})
    out.push_back({name, test::Builtin(name)});
  for (int k : {1, 2, 3, 5}) {
    if (k > 1) out.push_back({"half fan " + std::to_string(k), test::FanMesh(k, M_PI, 0.3)});
    out.push_back({"corner fan " + std::to_string(k), test::FanMesh(k, 0.5 * M_PI, 0.3)});
    out.push_back({"concave fan " + std::to_string(k), test::FanMesh(k + 1, 1.5 * M_PI, 0.3)});
  }
  out.push_back({"disk fan 7", test::FanMesh(7, 2 * M_PI, 0.4)});
  if (perturb) {
    std::uint32_t seed = 1;
    for (auto& m : out) test::Perturb(&m.second, 0.05, seed++);
  }
  return out;
}

double Angle(Vec3 a, Vec3 b) { return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)); }

SurfacePoint Eval(const ControlSurface& cs, const Displacement* d, Index f, Vec2 uv) {
  SurfacePoint p;
  REQUIRE(EvaluateSurface(*cs.domain, cs.patches.data(), d, f, uv, &p));
  REQUIRE(std::isfinite(p.position.x + p.position.y + p.position.z));
  REQUIRE(std::isfinite(p.normal.x + p.normal.y + p.normal.z));
  REQUIRE(glm::length(p.normal) == Approx(1.0).margin(1e-12));
  return p;
}

}  // namespace

TEST_CASE("the surface interpolates every control vertex from every incident face", "[surface]") {
  for (const auto& [name, mesh] : TestMeshes(true)) {
    INFO(name);
    const ControlSurface cs = test::Build(mesh);
    const MeshTopology& t = cs.domain->topology();
    const double diag = BoundingBoxDiagonal(cs.control.positions);
    const Vec2 corners[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (Index f = 0; f < t.num_faces(); ++f) {
      for (int a = 0; a < 4; ++a) {
        const SurfacePoint p = Eval(cs, nullptr, f, corners[a]);
        REQUIRE(glm::length(p.position - cs.control.positions[t.face_vertex(f, a)]) <=
                1e-12 * diag);
        // The normal at a vertex is the patch normal c10 x c01 (Yoon).
        const LocalPatch& lp = cs.patches[t.face_vertex(f, a)];
        const Vec3 n = glm::normalize(glm::cross(lp.coeff[1][0], lp.coeff[0][1]));
        REQUIRE(Angle(p.normal, n) < 1e-9);
      }
    }
  }
}

TEST_CASE("a planar control mesh gives a planar surface for any valence", "[surface]") {
  std::vector<PolygonMesh> meshes;
  for (int k = 3; k <= 12; ++k) meshes.push_back(test::FanMesh(k, 2 * M_PI));
  for (int k = 1; k <= 6; ++k) {
    if (k > 1) meshes.push_back(test::FanMesh(k, M_PI));  // one quad over pi is degenerate
    meshes.push_back(test::FanMesh(k, 0.5 * M_PI));
    meshes.push_back(test::FanMesh(k + 1, 1.5 * M_PI));
  }
  PolygonMesh flat_grid = test::Builtin("grid");
  for (Vec3& p : flat_grid.positions) p.z = 0.0;
  meshes.push_back(flat_grid);
  test::Lcg rng(9);
  for (size_t mi = 0; mi < meshes.size(); ++mi) {
    PolygonMesh m = meshes[mi];
    INFO("planar mesh " << mi << " with " << m.num_faces() << " faces");
    for (Vec3& p : m.positions) {  // random in-plane perturbation
      p.x += 0.05 * (rng.Next() - 0.5);
      p.y += 0.05 * (rng.Next() - 0.5);
    }
    for (ChartType type : {ChartType::kCharacteristicMap, ChartType::kFullyComplex}) {
      DomainOptions o;
      o.chart_type = type;
      const ControlSurface cs = test::Build(m, o);
      for (Index f = 0; f < cs.domain->num_faces(); ++f) {
        INFO("type " << int(type) << " face " << f);
        for (int i = 0; i < 30; ++i) {
          const SurfacePoint p = Eval(cs, nullptr, f, Vec2(rng.Next(), rng.Next()));
          REQUIRE(std::abs(p.position.z) < 1e-12);
          REQUIRE(std::abs(p.dx.z) < 1e-10);
          REQUIRE(std::abs(p.du.z) < 1e-10);
          // Planar always; orientation kept by the default characteristic map. The fully
          // complex map (p = q = 1/3 at a 3-face boundary corner) folds such fans near their
          // corner (docs/math.md), so only |n.z| = 1 is asserted for it.
          if (type == ChartType::kCharacteristicMap) {
            REQUIRE(p.normal.z == Approx(1.0).margin(1e-12));
          } else {
            REQUIRE(std::abs(p.normal.z) == Approx(1.0).margin(1e-12));
          }
        }
      }
    }
  }
}

TEST_CASE("analytic derivatives match finite differences", "[surface]") {
  test::Lcg rng(21);
  const test::WavyDisplacement wavy(0.05);
  for (const auto& [name, mesh] : TestMeshes(true)) {
    for (BlendType blend : {BlendType::kCInfinity, BlendType::kC2}) {
      DomainOptions o;
      o.blend_type = blend;
      const ControlSurface cs = test::Build(mesh, o);
      for (const Displacement* d :
           {static_cast<const Displacement*>(nullptr), static_cast<const Displacement*>(&wavy)}) {
        INFO(name << " blend " << int(blend) << (d ? " displaced" : " domain"));
        for (Index f = 0; f < cs.domain->num_faces(); ++f) {
          for (int i = 0; i < 6; ++i) {
            const Vec2 uv(0.01 + 0.98 * rng.Next(), 0.01 + 0.98 * rng.Next());
            const SurfacePoint p = Eval(cs, d, f, uv);
            REQUIRE(p.face_derivatives_valid);
            const double h = 1e-6;
            const Vec3 fu = (Eval(cs, d, f, uv + Vec2(h, 0)).position -
                             Eval(cs, d, f, uv - Vec2(h, 0)).position) /
                            (2 * h);
            const Vec3 fv = (Eval(cs, d, f, uv + Vec2(0, h)).position -
                             Eval(cs, d, f, uv - Vec2(0, h)).position) /
                            (2 * h);
            const double scale = 1.0 + glm::length(p.du) + glm::length(p.dv);
            REQUIRE(glm::length(p.du - fu) < 2e-6 * scale);
            REQUIRE(glm::length(p.dv - fv) < 2e-6 * scale);
            // The chart derivatives span the same oriented tangent plane.
            REQUIRE(Angle(glm::cross(p.du, p.dv), p.normal) < 1e-6);
          }
        }
      }
    }
  }
}

TEST_CASE("position and normal on every control edge agree from both faces", "[surface][edge]") {
  const test::WavyDisplacement wavy(0.05);
  const double ts[] = {0.0, 0.01, 0.05,  0.1, 0.125, 0.2,  0.3, 0.5,
                       0.7, 0.8,  0.875, 0.9, 0.95,  0.99, 1.0};
  for (const auto& [name, mesh] : TestMeshes(true)) {
    for (ChartType type : {ChartType::kCharacteristicMap, ChartType::kFullyComplex}) {
      DomainOptions o;
      o.chart_type = type;
      const ControlSurface cs = test::Build(mesh, o);
      const MeshTopology& topo = cs.domain->topology();
      const double diag = BoundingBoxDiagonal(cs.control.positions);
      for (const Displacement* d :
           {static_cast<const Displacement*>(nullptr), static_cast<const Displacement*>(&wavy)}) {
        INFO(name << " type " << int(type) << (d ? " displaced" : " domain"));
        double worst_pos = 0.0, worst_angle = 0.0;
        for (Index h = 0; h < topo.num_halfedges(); ++h) {
          const Index tw = topo.twin(h);
          if (tw == kInvalidIndex || tw < h) continue;
          const Index f0 = topo.halfedge_face(h), f1 = topo.halfedge_face(tw);
          const int k0 = static_cast<int>(h - topo.face_offset(f0));
          const int k1 = static_cast<int>(tw - topo.face_offset(f1));
          for (double t : ts) {
            // Point at fraction t from the origin of h; on the twin it is at 1 - t.
            const Vec2 uv0 = CornerToFace(k0, Vec2(t, 0.0));
            const Vec2 uv1 = CornerToFace(k1, Vec2(1.0 - t, 0.0));
            const SurfacePoint a = Eval(cs, d, f0, uv0), b = Eval(cs, d, f1, uv1);
            worst_pos = std::max(worst_pos, glm::length(a.position - b.position) / diag);
            worst_angle = std::max(worst_angle, Angle(a.normal, b.normal));
          }
        }
        CHECK(worst_pos <= 1e-9);
        CHECK(worst_angle <= 1e-6);
      }
    }
  }
}

TEST_CASE("normals are finite at vertices of degenerate control meshes", "[surface]") {
  PolygonMesh m = test::Builtin("cube");
  m.positions[6] = m.positions[5];  // a collapsed edge
  m.positions[7] = m.positions[5];  // and a collapsed top face
  const ControlSurface cs = test::Build(m);
  const Vec2 corners[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (Index f = 0; f < cs.domain->num_faces(); ++f) {
    for (int a = 0; a < 4; ++a) Eval(cs, nullptr, f, corners[a]);
    Eval(cs, nullptr, f, Vec2(0.5, 0.5));
  }
  // Invalid queries are rejected, not evaluated.
  SurfacePoint p;
  CHECK_FALSE(EvaluateSurface(*cs.domain, cs.patches.data(), nullptr, 99, {0.5, 0.5}, &p));
  CHECK_FALSE(EvaluateSurface(*cs.domain, cs.patches.data(), nullptr, 0, {1.5, 0.5}, &p));
  CHECK_FALSE(EvaluateSurface(*cs.domain, cs.patches.data(), nullptr, 0, {NAN, 0.5}, &p));
}

TEST_CASE("displacement moves the surface along the patch normal", "[surface]") {
  // With a constant displacement d, a point in the one-chart region of a vertex moves by
  // exactly d times the patch normal there (Eq. 3 with a single active chart).
  struct Constant final : Displacement {
    void Evaluate(Index, Vec2, double* value, Vec2* gradient) const override {
      *value = 0.1;
      *gradient = Vec2(0.0);
    }
  } constant;
  const ControlSurface cs = test::Build(test::Builtin("prism5"));
  for (Index f = 0; f < cs.domain->num_faces(); ++f) {
    const SurfacePoint base = Eval(cs, nullptr, f, Vec2(0.005, 0.008));
    const SurfacePoint moved = Eval(cs, &constant, f, Vec2(0.005, 0.008));
    REQUIRE(glm::length(moved.position - (base.position + 0.1 * base.normal)) < 1e-12);
  }
}

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/surface/chart.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "dermis/surface/manifold_domain.h"
#include "support/domains.h"

using namespace dermis;

namespace {
const ChartType kTypes[3] = {ChartType::kCharacteristicMap, ChartType::kFullyComplex,
                             ChartType::kIsodistance};

std::vector<ChartParams> AllCharts() {
  std::vector<ChartParams> charts;
  for (ChartType type : kTypes) {
    for (int k = 3; k <= 16; ++k) charts.push_back(MakeChartParams(k, VertexKind::kInterior, type));
    for (VertexKind kind :
         {VertexKind::kCrease, VertexKind::kConvexCorner, VertexKind::kConcaveCorner}) {
      for (int k = 1; k <= 8; ++k) charts.push_back(MakeChartParams(k, kind, type));
    }
  }
  return charts;
}
}  // namespace

TEST_CASE("characteristic-map exponents match the table of docs/notes/manifold.md section 2",
          "[chart]") {
  const double p[10] = {1.285963, 1.0,      0.862527, 0.786666, 0.740552,
                        0.710481, 0.689801, 0.674979, 0.663996, 0.655634};
  for (int k = 3; k <= 12; ++k) {
    const ChartParams c = MakeChartParams(k, VertexKind::kInterior, ChartType::kCharacteristicMap);
    CHECK(c.p == Approx(p[k - 3]).margin(1e-6));
    CHECK(c.q == Approx(4.0 / k).margin(1e-15));
    const ChartParams fc = MakeChartParams(k, VertexKind::kInterior, ChartType::kFullyComplex);
    CHECK(fc.p == Approx(4.0 / k).margin(1e-15));
  }
  CHECK(MakeChartParams(4, VertexKind::kInterior, ChartType::kCharacteristicMap).p == 1.0);
  CHECK(MakeChartParams(3, VertexKind::kCrease, ChartType::kFullyComplex).q == Approx(2.0 / 3));
  CHECK(MakeChartParams(2, VertexKind::kConcaveCorner, ChartType::kFullyComplex).q == Approx(1.5));
}

TEST_CASE("corner maps and relative corner maps are consistent", "[chart]") {
  test::Lcg rng(1);
  for (int i = 0; i < 200; ++i) {
    const Vec2 w(rng.Next(), rng.Next());
    for (int a = 0; a < 4; ++a) {
      const Vec2 back = FaceToCorner(a, CornerToFace(a, w));
      REQUIRE(back.x == Approx(w.x).margin(1e-15));
      REQUIRE(back.y == Approx(w.y).margin(1e-15));
      for (int delta = 0; delta < 4; ++delta) {
        const Vec2 direct = CornerTransition(delta, w);
        const Vec2 via_face = FaceToCorner((a + delta) % 4, CornerToFace(a, w));
        REQUIRE(direct.x == Approx(via_face.x).margin(1e-15));
        REQUIRE(direct.y == Approx(via_face.y).margin(1e-15));
      }
    }
    const Vec2 t13 = CornerTransition(1, CornerTransition(3, w));
    const Vec2 t22 = CornerTransition(2, CornerTransition(2, w));
    REQUIRE(t13.x == Approx(w.x).margin(1e-15));
    REQUIRE(t13.y == Approx(w.y).margin(1e-15));
    REQUIRE(t22.x == Approx(w.x).margin(1e-15));
    REQUIRE(t22.y == Approx(w.y).margin(1e-15));
  }
  // Corner a sits at its face corner; its c-axis points to the next corner.
  const Vec2 corners[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int a = 0; a < 4; ++a) {
    const Vec2 origin = CornerToFace(a, Vec2(0, 0));
    const Vec2 c_end = CornerToFace(a, Vec2(1, 0));
    const Vec2 d_end = CornerToFace(a, Vec2(0, 1));
    CHECK(origin == corners[a]);
    CHECK(c_end == corners[(a + 1) % 4]);
    CHECK(d_end == corners[(a + 3) % 4]);
    const glm::dmat2 j = FaceToCornerJacobian(a);
    const Vec2 w0 = FaceToCorner(a, Vec2(0.3, 0.4));
    const Vec2 ws = FaceToCorner(a, Vec2(1.3, 0.4)) - w0, wt = FaceToCorner(a, Vec2(0.3, 1.4)) - w0;
    CHECK(glm::length(j[0] - ws) < 1e-12);
    CHECK(glm::length(j[1] - wt) < 1e-12);
  }
}

TEST_CASE("chart maps invert for every valence, kind and chart type", "[chart]") {
  test::Lcg rng(2);
  for (const ChartParams& c : AllCharts()) {
    INFO("K=" << c.valence << " kind=" << int(c.kind) << " p=" << c.p);
    for (int i = 0; i < 100; ++i) {
      const int f = static_cast<int>(rng.Next() * c.valence);
      const Vec2 w(rng.Next(), rng.Next());
      Vec2 z;
      ChartMap(c, f, w, &z);
      int f2;
      Vec2 w2;
      REQUIRE(ChartMapInverse(c, z, &f2, &w2));
      // On the shared ray between faces either face is right; compare through the chart.
      Vec2 z2;
      ChartMap(c, f2, w2, &z2);
      REQUIRE(z2.x == Approx(z.x).margin(1e-12));
      REQUIRE(z2.y == Approx(z.y).margin(1e-12));
      if (f2 == f) {
        REQUIRE(w2.x == Approx(w.x).margin(1e-10));
        REQUIRE(w2.y == Approx(w.y).margin(1e-10));
      }
    }
    // The vertex maps to the origin and back to face 0.
    Vec2 z0;
    ChartMap(c, 0, Vec2(0.0), &z0);
    CHECK(z0 == Vec2(0.0));
  }
}

TEST_CASE("quarter-turn charts: the rotation, and the inverse on the axes and at -0", "[chart]") {
  // p = q = 1 charts map by exact quarter turns; the interior one's inverse takes the face from
  // the quadrant, angles [f pi/2, (f + 1) pi/2), whatever the sign of a zero coordinate.
  for (ChartType type :
       {ChartType::kCharacteristicMap, ChartType::kFullyComplex, ChartType::kIsodistance}) {
    const ChartParams chart = MakeChartParams(4, VertexKind::kInterior, type);
    REQUIRE(chart.p == 1.0);
    REQUIRE(chart.q == 1.0);
    struct Axis {
      Vec2 z;
      int face;
      Vec2 w;
    };
    const Axis axes[] = {{{1.0, 0.0}, 0, {1.0, 0.0}},       {{1.0, -0.0}, 0, {1.0, 0.0}},
                         {{0.0, 2.0}, 1, {2.0, 0.0}},       {{-0.0, 2.0}, 1, {2.0, 0.0}},
                         {{-3.0, 0.0}, 2, {3.0, 0.0}},      {{-3.0, -0.0}, 2, {3.0, 0.0}},
                         {{0.0, -0.5}, 3, {0.5, 0.0}},      {{-0.0, -0.5}, 3, {0.5, 0.0}},
                         {{0.25, 0.25}, 0, {0.25, 0.25}},   {{-0.25, 0.25}, 1, {0.25, 0.25}},
                         {{-0.25, -0.25}, 2, {0.25, 0.25}}, {{0.25, -0.25}, 3, {0.25, 0.25}}};
    for (const Axis& a : axes) {
      INFO("z = (" << a.z.x << ", " << a.z.y << ")");
      int f = -1;
      Vec2 w;
      REQUIRE(ChartMapInverse(chart, a.z, &f, &w));
      CHECK(f == a.face);
      CHECK(w.x == a.w.x);
      CHECK(w.y == a.w.y);
      CHECK_FALSE(std::signbit(w.x));
      CHECK_FALSE(std::signbit(w.y));
      Vec2 z;
      glm::dmat2 jac;
      REQUIRE(ChartMap(chart, f, w, &z, &jac));
      CHECK(z.x == a.z.x);
      CHECK(z.y == a.z.y);
      // The image of the face's c axis lies at angle f pi/2, never at -pi.
      Vec2 edge;
      ChartMap(chart, f, Vec2(1.0, 0.0), &edge);
      CHECK(std::atan2(edge.y, edge.x) ==
            Approx(f <= 2 ? f * 1.5707963267948966 : -1.5707963267948966));
      // The Jacobian is the rotation by f quarter turns.
      CHECK(jac[0].x == edge.x);
      CHECK(jac[0].y == edge.y);
      CHECK(jac[1].x == -edge.y);
      CHECK(jac[1].y == edge.x);
    }
    // At the vertex: the same rotation, and face 0.
    int f = -1;
    Vec2 w(1.0);
    REQUIRE(ChartMapInverse(chart, Vec2(0.0), &f, &w));
    CHECK(f == 0);
    CHECK(w == Vec2(0.0));
  }
}

TEST_CASE("chart landmarks and Jacobians", "[chart]") {
  for (const ChartParams& c : AllCharts()) {
    INFO("K=" << c.valence << " kind=" << int(c.kind) << " p=" << c.p);
    for (int f = 0; f < c.valence; ++f) {
      Vec2 e, d;
      ChartMap(c, f, Vec2(1, 0), &e);
      ChartMap(c, f, Vec2(1, 1), &d);
      const double wedge = c.sector / c.valence;
      CHECK(glm::length(e) == Approx(1.0).margin(1e-14));
      CHECK(std::atan2(e.y, e.x) == Approx(std::remainder(f * wedge, 2 * M_PI)).margin(1e-12));
      CHECK(glm::length(d) == Approx(std::pow(std::sqrt(2.0), c.p)).margin(1e-14));
      const double da = std::remainder((f + 0.5) * wedge, 2 * M_PI);
      CHECK(std::atan2(d.y, d.x) == Approx(da).margin(1e-12));
      // Jacobian against central differences.
      for (Vec2 w : {Vec2(0.3, 0.2), Vec2(0.9, 0.05), Vec2(0.01, 0.7), Vec2(0.6, 0.6)}) {
        Vec2 z;
        glm::dmat2 j;
        REQUIRE(ChartMap(c, f, w, &z, &j));
        const double h = 1e-6;
        Vec2 zp, zm;
        ChartMap(c, f, w + Vec2(h, 0), &zp);
        ChartMap(c, f, w - Vec2(h, 0), &zm);
        const Vec2 dc = (zp - zm) / (2 * h);
        ChartMap(c, f, w + Vec2(0, h), &zp);
        ChartMap(c, f, w - Vec2(0, h), &zm);
        const Vec2 dd = (zp - zm) / (2 * h);
        REQUIRE(j[0].x == Approx(dc.x).margin(1e-6));
        REQUIRE(j[0].y == Approx(dc.y).margin(1e-6));
        REQUIRE(j[1].x == Approx(dd.x).margin(1e-6));
        REQUIRE(j[1].y == Approx(dd.y).margin(1e-6));
        REQUIRE(glm::determinant(j) > 0.0);  // orientation preserving
        if (c.p == c.q) {                    // holomorphic: Cauchy-Riemann
          REQUIRE(j[0].x == Approx(j[1].y).margin(1e-12));
          REQUIRE(j[0].y == Approx(-j[1].x).margin(1e-12));
        }
      }
    }
  }
  // At an extraordinary vertex the chart map is not differentiable; at a regular one it is.
  glm::dmat2 j;
  Vec2 z;
  CHECK_FALSE(ChartMap(MakeChartParams(5, VertexKind::kInterior, ChartType::kCharacteristicMap), 0,
                       Vec2(0.0), &z, &j));
  CHECK(ChartMap(MakeChartParams(4, VertexKind::kInterior, ChartType::kCharacteristicMap), 0,
                 Vec2(0.0), &z, &j));
}

TEST_CASE("neighbouring faces of a chart meet along their shared edge", "[chart]") {
  // The d-axis of ring face f and the c-axis of ring face f+1 are the same ray in the chart.
  for (const ChartParams& c : AllCharts()) {
    const int last = c.kind == VertexKind::kInterior ? c.valence : c.valence - 1;
    for (int f = 0; f < last; ++f) {
      for (double t : {0.1, 0.5, 0.9}) {
        Vec2 a, b;
        ChartMap(c, f, Vec2(0.0, t), &a);
        ChartMap(c, (f + 1) % c.valence, Vec2(t, 0.0), &b);
        REQUIRE(a.x == Approx(b.x).margin(1e-13));
        REQUIRE(a.y == Approx(b.y).margin(1e-13));
      }
    }
  }
}

TEST_CASE("transition maps composed both ways are the identity", "[chart][transition]") {
  test::Lcg rng(3);
  for (const char* name : {"cube", "prism5", "prism9", "house", "grid", "torus", "octahedron"}) {
    for (ChartType type : kTypes) {
      INFO(name << " chart type " << int(type));
      DomainOptions o;
      o.chart_type = type;
      const ControlSurface cs = test::Build(test::Builtin(name), o);
      const ManifoldDomain& d = *cs.domain;
      for (Index f = 0; f < d.num_faces(); ++f) {
        for (int i = 0; i < 5; ++i) {
          const Vec2 uv(0.02 + 0.96 * rng.Next(), 0.02 + 0.96 * rng.Next());
          for (int a = 0; a < 4; ++a) {
            const Index vi = d.topology().face_vertex(f, a);
            const Vec2 zi = d.FaceToChart(f, a, uv);
            // Chart to face recovers the point.
            Index f2;
            Vec2 uv2;
            REQUIRE(d.ChartToFace(vi, zi, &f2, &uv2));
            REQUIRE(f2 == f);
            REQUIRE(uv2.x == Approx(uv.x).margin(1e-10));
            REQUIRE(uv2.y == Approx(uv.y).margin(1e-10));
            for (int b = 0; b < 4; ++b) {
              const Index vj = d.topology().face_vertex(f, b);
              Vec2 zj, back;
              REQUIRE(d.Transition(vi, zi, vj, &zj));
              const Vec2 expect = d.FaceToChart(f, b, uv);
              REQUIRE(zj.x == Approx(expect.x).margin(1e-10));
              REQUIRE(zj.y == Approx(expect.y).margin(1e-10));
              REQUIRE(d.Transition(vj, zj, vi, &back));
              REQUIRE(back.x == Approx(zi.x).margin(1e-10));
              REQUIRE(back.y == Approx(zi.y).margin(1e-10));
            }
          }
        }
      }
    }
  }
}

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>

#include "dermis/offline/build/patch_fit_operator.h"
#include "dermis/surface/local_patch.h"
#include "support/domains.h"

using namespace dermis;

namespace {
struct Case {
  ChartParams chart;
  std::string name;
};
std::vector<Case> Cases() {
  std::vector<Case> out;
  for (ChartType type :
       {ChartType::kCharacteristicMap, ChartType::kFullyComplex, ChartType::kIsodistance}) {
    for (int k = 3; k <= 16; ++k) {
      out.push_back({MakeChartParams(k, VertexKind::kInterior, type),
                     "interior K=" + std::to_string(k) + " type " + std::to_string(int(type))});
    }
    for (VertexKind kind :
         {VertexKind::kCrease, VertexKind::kConvexCorner, VertexKind::kConcaveCorner}) {
      for (int k = 1; k <= 8; ++k) {
        out.push_back({MakeChartParams(k, kind, type),
                       "boundary kind " + std::to_string(int(kind)) + " K=" + std::to_string(k)});
      }
    }
  }
  return out;
}

// Applies the operator to ring values f(z_k) (3 channels) and returns the patch.
template <typename F>
LocalPatch FitRing(const ChartParams& chart, const std::vector<double>& op, F f) {
  const std::vector<Vec2> z = PatchRingChartPositions(chart);
  const int n = static_cast<int>(z.size());
  LocalPatch p;
  p.coeff[0][0] = f(Vec2(0.0));
  for (int row = 0; row < 8; ++row) {
    Vec3 c(0.0);
    for (int col = 0; col < n; ++col) c += op[row * n + col] * (f(z[col]) - p.coeff[0][0]);
    p.coeff[kPatchMonomials[row][0]][kPatchMonomials[row][1]] = c;
  }
  return p;
}
}  // namespace

TEST_CASE("patch-fit ranks: valence 3 is under-determined, 4 and up are full", "[patch]") {
  for (const Case& c : Cases()) {
    INFO(c.name);
    std::vector<double> op;
    int rank = 0;
    REQUIRE(ComputePatchFitOperator(c.chart, &op, &rank).ok());
    if (c.chart.kind == VertexKind::kInterior) CHECK(rank == (c.chart.valence == 3 ? 6 : 8));
    REQUIRE(op.size() == 8u * PatchRingChartPositions(c.chart).size());
  }
}

TEST_CASE("every patch fit reproduces linear functions exactly", "[patch]") {
  for (const Case& c : Cases()) {
    INFO(c.name);
    std::vector<double> op;
    REQUIRE(ComputePatchFitOperator(c.chart, &op).ok());
    const Vec3 v0(0.3, -1.0, 2.0), a(1.0, 0.2, -0.5), b(-0.4, 0.9, 0.1);
    const LocalPatch p = FitRing(c.chart, op, [&](Vec2 z) { return v0 + z.x * a + z.y * b; });
    for (int m = 0; m < 3; ++m)
      for (int n = 0; n < 3; ++n) {
        const Vec3 expect = m == 0 && n == 0   ? v0
                            : m == 1 && n == 0 ? a
                            : m == 0 && n == 1 ? b
                                               : Vec3(0.0);
        REQUIRE(glm::length(p.coeff[m][n] - expect) < 1e-10);
      }
  }
}

TEST_CASE("full-rank fits reproduce bi-quadratics; valence 3 and 4 interpolate their ring",
          "[patch]") {
  test::Lcg rng(11);
  for (const Case& c : Cases()) {
    INFO(c.name);
    std::vector<double> op;
    int rank = 0;
    REQUIRE(ComputePatchFitOperator(c.chart, &op, &rank).ok());
    LocalPatch truth;
    for (int m = 0; m < 3; ++m)
      for (int n = 0; n < 3; ++n) truth.coeff[m][n] = Vec3(rng.Next(), rng.Next(), rng.Next());
    auto eval = [&](const LocalPatch& p, Vec2 z) {
      PatchJet j;
      EvaluatePatch(p, z, &j);
      return j.p;
    };
    const LocalPatch fit = FitRing(c.chart, op, [&](Vec2 z) { return eval(truth, z); });
    if (rank == 8) {
      for (int m = 0; m < 3; ++m)
        for (int n = 0; n < 3; ++n)
          REQUIRE(glm::length(fit.coeff[m][n] - truth.coeff[m][n]) < 1e-9);
    }
    if (c.chart.kind == VertexKind::kInterior && c.chart.valence <= 4) {
      // Random ring positions (not from a bi-quadratic) are interpolated exactly.
      const std::vector<Vec2> z = PatchRingChartPositions(c.chart);
      std::vector<Vec3> values(z.size());
      for (Vec3& v : values) v = Vec3(rng.Next(), rng.Next(), rng.Next());
      size_t k = 0;
      const LocalPatch interp = FitRing(c.chart, op, [&](Vec2 q) {
        if (q == Vec2(0.0)) return Vec3(0.5);
        return values[k++ % values.size()];
      });
      for (size_t i = 0; i < z.size(); ++i)
        REQUIRE(glm::length(eval(interp, z[i]) - values[i]) < 1e-9);
    }
  }
}

TEST_CASE("a refit after moving control vertices equals a fit from scratch", "[patch]") {
  PolygonMesh mesh = test::Builtin("prism6");
  const ControlSurface cs = test::Build(mesh);
  std::vector<Vec3> moved = cs.control.positions;
  test::Lcg rng(5);
  for (Vec3& p : moved) p += Vec3(rng.Next(), rng.Next(), rng.Next()) * 0.2;
  std::vector<LocalPatch> refit(moved.size());
  cs.domain->FitPatches(moved.data(), refit.data());
  // The same fit, done independently: least squares over the ring with the operator's rows.
  for (Index v = 0; v < cs.domain->num_vertices(); ++v) {
    const std::vector<Vec2> z = PatchRingChartPositions(cs.domain->chart(v));
    const Index* ring = cs.domain->patch_ring(v);
    // Residual of the fit must be orthogonal to every monomial column (normal equations) for
    // full-rank rings.
    for (int j = 0; j < 8; ++j) {
      Vec3 dot(0.0);
      for (size_t k = 0; k < z.size(); ++k) {
        PatchJet jet;
        EvaluatePatch(refit[v], z[k], &jet);
        const double mono =
            std::pow(z[k].x, kPatchMonomials[j][0]) * std::pow(z[k].y, kPatchMonomials[j][1]);
        dot += mono * (moved[ring[k]] - jet.p);
      }
      REQUIRE(glm::length(dot) < 1e-9);
    }
    REQUIRE(refit[v].coeff[0][0] == moved[v]);
  }
}

TEST_CASE("seam patch fits: the boundary restriction depends on the crease alone", "[patch]") {
  // A cut crease (docs/characters.md, "Hard edges cut open"): along its boundary rays a seam
  // patch is fixed by the vertex and its two boundary neighbours (ring entries 0 and n - 1),
  // so the two sides of the cut, whose other ring vertices differ, meet in one curve.
  struct Seam {
    VertexKind kind;
    SeamMode mode;
  };
  for (ChartType type : {ChartType::kCharacteristicMap, ChartType::kIsodistance}) {
    for (const Seam& s : {Seam{VertexKind::kCrease, SeamMode::kSmooth},
                          Seam{VertexKind::kConvexCorner, SeamMode::kSmooth},
                          Seam{VertexKind::kConcaveCorner, SeamMode::kSmooth},
                          Seam{VertexKind::kConvexCorner, SeamMode::kCorner},
                          Seam{VertexKind::kConcaveCorner, SeamMode::kCorner}}) {
      for (int k = 1; k <= 6; ++k) {
        const ChartParams chart = MakeChartParams(k, s.kind, type);
        INFO("kind " << int(s.kind) << " mode " << int(s.mode) << " K=" << k);
        std::vector<double> op;
        REQUIRE(ComputeSeamPatchFitOperator(chart, s.mode, &op).ok());
        const std::vector<Vec2> z = PatchRingChartPositions(chart);
        const int n = static_cast<int>(z.size());
        REQUIRE(op.size() == 8u * static_cast<std::size_t>(n));
        // Values on the ring: the boundary neighbours d1 (ray 1, chart +x) and d2 (the last
        // entry), the vertex at 0, and arbitrary others; then the same with every other ring
        // value changed: the patch along both rays is the same.
        const Vec3 d1(1.0, 0.3, -0.2), d2(-0.9, 0.4, 0.5);
        auto ring = [&](double other_scale) {
          return [&, other_scale](Vec2 w) {
            for (int i = 0; i < n; ++i) {
              if (glm::length(w - z[static_cast<std::size_t>(i)]) > 1e-12) continue;
              if (i == 0) return d1;
              if (i == n - 1) return d2;
              return other_scale * Vec3(0.7 * w.x - 0.2, w.y * w.y + 0.4, 0.3 * w.x * w.y + 1.1);
            }
            return Vec3(0.0);  // the vertex
          };
        };
        const LocalPatch a = FitRing(chart, op, ring(1.0)), b = FitRing(chart, op, ring(-2.5));
        const Vec2 u2 = z.back();  // the second ray's direction
        for (int i = 0; i <= 10; ++i) {
          const double t = i / 10.0;
          for (const Vec2 dir : {Vec2(1.0, 0.0), u2}) {
            PatchJet ja, jb;
            EvaluatePatch(a, t * dir, &ja);
            EvaluatePatch(b, t * dir, &jb);
            CHECK(glm::length(ja.p - jb.p) < 1e-12);
          }
        }
        // The neighbours are interpolated: the curve reaches them at t = 1; in kSmooth it is
        // the parabola v + a t + b t^2 with t = 1 at d1 and -1 at d2, in kCorner a line to each.
        for (int r = 0; r < 2; ++r) {
          const Vec2 dir = r == 0 ? Vec2(1.0, 0.0) : u2;
          const Vec3 end = r == 0 ? d1 : d2;
          for (int i = 0; i <= 4; ++i) {
            const double t = i / 4.0;
            const double tt = r == 0 ? t : -t;
            const Vec3 expect = s.mode == SeamMode::kSmooth
                                    ? 0.5 * (d1 - d2) * tt + 0.5 * (d1 + d2) * tt * tt
                                    : t * end;
            PatchJet j;
            EvaluatePatch(a, t * dir, &j);
            CHECK(glm::length(j.p - expect) < 1e-12);
          }
        }
        // A plane through the ring is reproduced where the chart's rays are opposite (a
        // half-disk) or the mode draws straight lines to the neighbours.
        if (s.kind == VertexKind::kCrease || s.mode == SeamMode::kCorner) {
          const Vec3 v0(0.0), pa(1.0, 0.2, -0.5), pb(-0.4, 0.9, 0.1);
          const LocalPatch p = FitRing(chart, op, [&](Vec2 w) { return v0 + w.x * pa + w.y * pb; });
          for (int m = 0; m < 3; ++m)
            for (int q = 0; q < 3; ++q) {
              const Vec3 expect = m == 1 && q == 0 ? pa : m == 0 && q == 1 ? pb : Vec3(0.0);
              if (m == 0 && q == 0) continue;
              CHECK(glm::length(p.coeff[m][q] - expect) < 1e-10);
            }
        }
      }
    }
  }
  // kNone is the ordinary operator; an interior chart, or corner lines on a half-disk (both
  // rays on one axis), are refused.
  const ChartParams crease = MakeChartParams(3, VertexKind::kCrease, ChartType::kCharacteristicMap);
  std::vector<double> plain, none;
  REQUIRE(ComputePatchFitOperator(crease, &plain).ok());
  REQUIRE(ComputeSeamPatchFitOperator(crease, SeamMode::kNone, &none).ok());
  CHECK(plain == none);
  std::vector<double> op;
  CHECK(ComputeSeamPatchFitOperator(crease, SeamMode::kCorner, &op).code() ==
        StatusCode::kInvalidInput);
  CHECK(ComputeSeamPatchFitOperator(
            MakeChartParams(4, VertexKind::kInterior, ChartType::kCharacteristicMap),
            SeamMode::kSmooth, &op)
            .code() == StatusCode::kInvalidInput);
}

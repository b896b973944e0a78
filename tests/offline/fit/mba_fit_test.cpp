// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Multilevel B-spline approximation (docs/notes/fit.md section 1): refinement is exact, truncation
// equals the coarser fit, a smooth function is reproduced and the error falls with levels.
#include "dermis/offline/fit/mba_fit.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "dermis/surface/bspline_displacement.h"
#include "test_meshes.h"

using namespace dermis;
using namespace dermis::test;

namespace {

double Smooth(Vec2 z) { return 0.3 * std::sin(2.0 * z.x) * std::cos(1.5 * z.y) + 0.1 * z.x * z.y; }

// Evaluates one level-k lattice of a double array the way the runtime does.
double EvalLattice(const double* lattice, int level, double r, Vec2 z) {
  const int m = 1 << level;
  int i = 0, j = 0;
  double s = 0.0, t = 0.0, bs[4], bt[4], d[4];
  BsplineCell((z.x + r) * m / (2 * r), m, &i, &s);
  BsplineCell((z.y + r) * m / (2 * r), m, &j, &t);
  CubicBsplineBasis(s, bs, d);
  CubicBsplineBasis(t, bt, d);
  double f = 0.0;
  for (int l = 0; l < 4; ++l) {
    for (int k = 0; k < 4; ++k) f += bs[k] * bt[l] * lattice[(j + l) * (m + 3) + i + k];
  }
  return f;
}

std::vector<Vec2> RandomPoints(int n, double r, Lcg* rng) {
  std::vector<Vec2> z(static_cast<std::size_t>(n));
  for (Vec2& p : z) p = Vec2(rng->Uniform(-r, r), rng->Uniform(-r, r));
  return z;
}

}  // namespace

TEST_CASE("mba: basis is a partition of unity with exact derivatives") {
  for (double t = 0.0; t <= 1.0; t += 0.125) {
    double b[4], db[4], bh[4], dbh[4];
    CubicBsplineBasis(t, b, db);
    CHECK(b[0] + b[1] + b[2] + b[3] == Approx(1.0).margin(1e-15));
    CHECK(db[0] + db[1] + db[2] + db[3] == Approx(0.0).margin(1e-15));
    const double h = 1e-6;
    CubicBsplineBasis(t + h, bh, dbh);
    for (int k = 0; k < 4; ++k) CHECK((bh[k] - b[k]) / h == Approx(db[k]).margin(1e-5));
  }
}

TEST_CASE("mba: refinement reproduces the coarse function exactly") {
  Lcg rng(7);
  for (int m : {1, 2, 4, 8}) {
    std::vector<double> coarse(static_cast<std::size_t>((m + 3) * (m + 3)));
    for (double& c : coarse) c = rng.Uniform(-1.0, 1.0);
    std::vector<double> fine(static_cast<std::size_t>((2 * m + 3) * (2 * m + 3)));
    RefineBsplineLattice(coarse.data(), m, fine.data());
    const int level = static_cast<int>(std::log2(m));
    for (int n = 0; n < 200; ++n) {
      const Vec2 z(rng.Uniform(-1.0, 1.0), rng.Uniform(-1.0, 1.0));
      CHECK(EvalLattice(fine.data(), level + 1, 1.0, z) ==
            Approx(EvalLattice(coarse.data(), level, 1.0, z)).margin(1e-13));
    }
  }
}

TEST_CASE("mba: reproduces a smooth function and converges with levels") {
  Lcg rng(11);
  const double r = 1.0;
  const std::vector<Vec2> z = RandomPoints(4000, r, &rng);
  std::vector<double> values;
  for (const Vec2& p : z) values.push_back(Smooth(p));
  const std::vector<Vec2> probe = RandomPoints(500, 0.9 * r, &rng);
  double previous = 1e9;
  for (int levels = 2; levels <= 6; ++levels) {
    std::vector<double> lattices, residuals;
    FitMultilevelBspline(z.data(), values.data(), z.size(), r, levels, &lattices, &residuals);
    std::size_t offset = 0;
    for (int k = 0; k + 1 < levels; ++k) offset += static_cast<std::size_t>(BsplineLatticeSize(k));
    double err = 0.0;
    for (const Vec2& p : probe) {
      err = std::max(err,
                     std::abs(EvalLattice(lattices.data() + offset, levels - 1, r, p) - Smooth(p)));
    }
    // Residuals returned are those of the merged function.
    for (std::size_t c = 0; c < z.size(); c += 97) {
      CHECK(residuals[c] ==
            Approx(values[c] - EvalLattice(lattices.data() + offset, levels - 1, r, z[c]))
                .margin(1e-12));
    }
    INFO("levels " << levels << " max error " << err);
    CHECK(err < previous);
    previous = err;
  }
  CHECK(previous < 2e-3);  // 32 cells per side for a function of unit-scale features
}

TEST_CASE("mba: truncating to L levels equals an L-level fit, in the runtime too") {
  Lcg rng(3);
  const std::vector<Vec2> z = RandomPoints(700, 0.7, &rng);
  std::vector<double> values;
  for (const Vec2& p : z) values.push_back(Smooth(p) + 0.01 * std::sin(40.0 * p.x));
  std::vector<double> full;
  FitMultilevelBspline(z.data(), values.data(), z.size(), 0.8, 6, &full);
  for (int levels = 1; levels <= 6; ++levels) {
    std::vector<double> part;
    FitMultilevelBspline(z.data(), values.data(), z.size(), 0.8, levels, &part);
    REQUIRE(part.size() <= full.size());
    for (std::size_t i = 0; i < part.size(); ++i) REQUIRE(part[i] == full[i]);
  }
  // The runtime evaluates level L from the stored merged lattices.
  BsplineDisplacementData data;
  data.half_extent = {0.8};
  data.num_levels = {6};
  data.offsets = {0, static_cast<std::int64_t>(full.size())};
  for (double v : full) data.values.push_back(static_cast<float>(v));
  Status s;
  auto d = BsplineDisplacement::Create(data, 1, &s);
  REQUIRE(d);
  for (int levels = 0; levels <= 7; ++levels) {
    std::size_t offset = 0;
    const int use = std::min(levels, 6);
    for (int k = 0; k + 1 < use; ++k) offset += static_cast<std::size_t>(BsplineLatticeSize(k));
    for (int n = 0; n < 50; ++n) {
      const Vec2 p(rng.Uniform(-0.8, 0.8), rng.Uniform(-0.8, 0.8));
      double v = 0.0;
      Vec2 g;
      d->EvaluateLevels(0, p, levels, &v, &g);
      const double expected = use == 0 ? 0.0 : EvalLattice(full.data() + offset, use - 1, 0.8, p);
      CHECK(v == Approx(expected).margin(1e-6));  // float storage
      // Gradient against central differences.
      const double h = 1e-5;
      double vx0, vx1, vy0, vy1;
      Vec2 unused;
      d->EvaluateLevels(0, p - Vec2(h, 0), levels, &vx0, &unused);
      d->EvaluateLevels(0, p + Vec2(h, 0), levels, &vx1, &unused);
      d->EvaluateLevels(0, p - Vec2(0, h), levels, &vy0, &unused);
      d->EvaluateLevels(0, p + Vec2(0, h), levels, &vy1, &unused);
      CHECK(g.x == Approx((vx1 - vx0) / (2 * h)).margin(1e-4));
      CHECK(g.y == Approx((vy1 - vy0) / (2 * h)).margin(1e-4));
    }
  }
}

TEST_CASE("mba: invalid displacement data is rejected") {
  BsplineDisplacementData data;
  data.half_extent = {1.0};
  data.num_levels = {2};
  data.offsets = {0, 3};
  data.values = {0.f, 0.f, 0.f};
  Status s;
  CHECK_FALSE(BsplineDisplacement::Create(data, 1, &s));
  CHECK(s.message().find("offsets") != std::string::npos);
  data.offsets = {0, 16 + 25};
  data.values.assign(41, 0.f);
  data.values[5] = std::nanf("");
  CHECK_FALSE(BsplineDisplacement::Create(data, 1, &s));
  data.values[5] = 0.f;
  data.half_extent = {-1.0};
  CHECK_FALSE(BsplineDisplacement::Create(data, 1, &s));
  data.half_extent = {1.0};
  CHECK(BsplineDisplacement::Create(data, 1, &s));
  CHECK_FALSE(BsplineDisplacement::Create(data, 2, &s));
}

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Multilevel B-spline displacements in both storage forms (dermis/surface/bspline_displacement.h):
// the additive sparse levels of .dsurf version 3 against a brute-force sum of B-splines over
// the listed nodes, truncation to fewer levels, dense levels without node lists, gradients, and
// the validation of bad data.
#include "dermis/surface/bspline_displacement.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "support/meshes.h"

namespace dermis {
namespace {

// The uniform cubic B-spline B((x - n) + 2) centred on node n, written out piecewise (an
// independent form of the basis: B(t) for t in [0, 4), the support of one node).
double CardinalBspline(double t) {
  if (t < 0.0 || t >= 4.0) return 0.0;
  if (t < 1.0) return t * t * t / 6.0;
  if (t < 2.0) return (-3.0 * t * t * t + 12.0 * t * t - 12.0 * t + 4.0) / 6.0;
  if (t < 3.0) return (3.0 * t * t * t - 24.0 * t * t + 60.0 * t - 44.0) / 6.0;
  return (4.0 - t) * (4.0 - t) * (4.0 - t) / 6.0;
}

// Value of one lattice at chart point z by summing every listed node's tensor B-spline:
// node (i, j) (lattice indices -1 .. m + 1) covers lattice coordinates (i - 2, i + 2).
double BruteLevel(const std::vector<std::uint32_t>& nodes, const std::vector<float>& values,
                  int level, double half, Vec2 z) {
  const int m = 1 << level;
  const int stride = m + 3;
  const double x = std::clamp((z.x + half) * m / (2.0 * half), 0.0, static_cast<double>(m));
  const double y = std::clamp((z.y + half) * m / (2.0 * half), 0.0, static_cast<double>(m));
  double f = 0.0;
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const int i = static_cast<int>(nodes[k] % static_cast<std::uint32_t>(stride)) - 1;
    const int j = static_cast<int>(nodes[k] / static_cast<std::uint32_t>(stride)) - 1;
    f += values[k] * CardinalBspline(x - i + 2.0) * CardinalBspline(y - j + 2.0);
  }
  return f;
}

struct Level {
  std::vector<std::uint32_t> nodes;
  std::vector<float> values;
};

// Random sparse levels for one chart: level k keeps each node with probability `keep`
// (dense when keep >= 1).
std::vector<Level> RandomLevels(int levels, double keep, test::Lcg* rng) {
  std::vector<Level> out(static_cast<std::size_t>(levels));
  for (int k = 0; k < levels; ++k) {
    for (std::int64_t n = 0; n < BsplineLatticeSize(k); ++n) {
      if (keep < 1.0 && rng->Next() >= keep) continue;
      out[static_cast<std::size_t>(k)].nodes.push_back(static_cast<std::uint32_t>(n));
      out[static_cast<std::size_t>(k)].values.push_back(
          static_cast<float>(rng->Uniform(-1.0, 1.0) / (1 << k)));
    }
  }
  return out;
}

BsplineDisplacementData Additive(const std::vector<std::vector<Level>>& charts, double half) {
  BsplineDisplacementData d;
  d.form = BsplineLevelForm::kAdditive;
  d.offsets.push_back(0);
  for (const std::vector<Level>& levels : charts) {
    d.half_extent.push_back(half);
    d.num_levels.push_back(static_cast<std::uint8_t>(levels.size()));
    for (std::size_t k = 0; k < levels.size(); ++k) {
      const Level& l = levels[k];
      d.level_counts.push_back(static_cast<std::int32_t>(l.nodes.size()));
      if (static_cast<std::int64_t>(l.nodes.size()) != BsplineLatticeSize(static_cast<int>(k))) {
        d.nodes.insert(d.nodes.end(), l.nodes.begin(), l.nodes.end());
      }
      d.values.insert(d.values.end(), l.values.begin(), l.values.end());
    }
    d.offsets.push_back(static_cast<std::int64_t>(d.values.size()));
  }
  return d;
}

}  // namespace

TEST_CASE("displacement: sparse additive levels sum the listed nodes' B-splines",
          "[displacement]") {
  test::Lcg rng(5);
  const double half = 1.3;
  // Chart 0 sparse, chart 1 dense, chart 2 without levels, chart 3 with an empty level 1.
  std::vector<std::vector<Level>> charts = {
      RandomLevels(5, 0.4, &rng), RandomLevels(4, 1.0, &rng), {}, RandomLevels(3, 0.3, &rng)};
  charts[3][1] = Level{};
  Status s;
  auto d = BsplineDisplacement::Create(Additive(charts, half), 4, &s);
  INFO(s.message());
  REQUIRE(d);
  CHECK(d->max_levels() == 5);
  std::int64_t total = 0;
  for (const auto& c : charts)
    for (const Level& l : c) total += static_cast<std::int64_t>(l.values.size());
  CHECK(d->num_coefficients() == total);
  CHECK(d->level_coefficients(1) ==
        static_cast<std::int64_t>(charts[0][1].values.size() + charts[1][1].values.size()));
  for (int n = 0; n < 300; ++n) {
    // Inside the square and a little outside it (clamped onto the square).
    const Vec2 z(rng.Uniform(-1.5, 1.5), rng.Uniform(-1.5, 1.5));
    for (std::size_t c = 0; c < charts.size(); ++c) {
      for (int levels = 0; levels <= 6; ++levels) {
        double expected = 0.0;
        for (int k = 0; k < std::min<int>(levels, static_cast<int>(charts[c].size())); ++k) {
          const Level& l = charts[c][static_cast<std::size_t>(k)];
          expected += BruteLevel(l.nodes, l.values, k, half, z);
        }
        double v = 0.0;
        Vec2 g;
        d->EvaluateLevels(static_cast<Index>(c), z, levels, &v, &g);
        CHECK(v == Approx(expected).margin(1e-12));
        TruncatedDisplacement t(d.get(), levels);
        double tv = 0.0;
        t.Evaluate(static_cast<Index>(c), z, &tv, &g);
        CHECK(tv == v);
      }
      double all = 0.0;
      Vec2 g;
      d->Evaluate(static_cast<Index>(c), z, &all, &g);
      double five = 0.0;
      d->EvaluateLevels(static_cast<Index>(c), z, 5, &five, &g);
      CHECK(all == five);
    }
  }
}

TEST_CASE("displacement: sparse gradients match finite differences; a dense level needs no list",
          "[displacement]") {
  test::Lcg rng(9);
  const double half = 0.9;
  const std::vector<std::vector<Level>> sparse = {RandomLevels(4, 0.5, &rng)};
  Status s;
  auto d = BsplineDisplacement::Create(Additive(sparse, half), 1, &s);
  REQUIRE(d);
  for (int n = 0; n < 100; ++n) {
    const Vec2 z(rng.Uniform(-0.85, 0.85), rng.Uniform(-0.85, 0.85));
    double v = 0.0, vx0, vx1, vy0, vy1;
    Vec2 g, unused;
    const double h = 1e-6;
    d->Evaluate(0, z, &v, &g);
    d->Evaluate(0, z - Vec2(h, 0), &vx0, &unused);
    d->Evaluate(0, z + Vec2(h, 0), &vx1, &unused);
    d->Evaluate(0, z - Vec2(0, h), &vy0, &unused);
    d->Evaluate(0, z + Vec2(0, h), &vy1, &unused);
    CHECK(g.x == Approx((vx1 - vx0) / (2 * h)).margin(1e-5));
    CHECK(g.y == Approx((vy1 - vy0) / (2 * h)).margin(1e-5));
  }
  // Every node listed explicitly but one: sparse storage of almost a dense level evaluates as
  // the brute-force sum too.
  std::vector<std::vector<Level>> full = {RandomLevels(3, 1.0, &rng)};
  Level& l2 = full[0][2];
  l2.nodes.erase(l2.nodes.begin() + 17);
  l2.values.erase(l2.values.begin() + 17);
  auto d2 = BsplineDisplacement::Create(Additive(full, half), 1, &s);
  REQUIRE(d2);
  CHECK(d2->data().nodes.size() == l2.nodes.size());  // levels 0 and 1 dense, no list
  for (int n = 0; n < 50; ++n) {
    const Vec2 z(rng.Uniform(-0.9, 0.9), rng.Uniform(-0.9, 0.9));
    double expected = 0.0;
    for (int k = 0; k < 3; ++k) {
      expected += BruteLevel(full[0][static_cast<std::size_t>(k)].nodes,
                             full[0][static_cast<std::size_t>(k)].values, k, half, z);
    }
    double v = 0.0;
    Vec2 g;
    d2->Evaluate(0, z, &v, &g);
    CHECK(v == Approx(expected).margin(1e-12));
  }
}

TEST_CASE("displacement: a fine level with fewer nodes than rows needs no row table",
          "[displacement]") {
  // A sparse level's nodes are found through a table of its lattice rows (2^k + 4 starts), or,
  // with fewer nodes than rows, by searching them whole: the same nodes, the same sums, without
  // the table (4 (2^9 + 4) = 2,064 bytes at level 9 for the 3 nodes below).
  test::Lcg rng(11);
  const double half = 1.1;
  std::vector<std::vector<Level>> charts = {RandomLevels(9, 1.0, &rng)};
  // Levels 0..8 dense; level 9 (515 x 515 nodes, 515 rows) with 3 nodes, one row shared by
  // two; a second chart whose level 5 (35 rows) has exactly 35 nodes (a table) and level 6
  // (67 rows) 66 (none).
  Level fine;
  const std::uint32_t stride9 = (1u << 9) + 3;
  for (std::uint32_t n : {200u * stride9 + 250u, 200u * stride9 + 252u, 300u * stride9 + 10u}) {
    fine.nodes.push_back(n);
    fine.values.push_back(static_cast<float>(rng.Uniform(-1.0, 1.0)));
  }
  charts[0].push_back(fine);
  charts.push_back(RandomLevels(5, 1.0, &rng));
  for (int k : {5, 6}) {
    const std::uint32_t rows = (1u << k) + 3;
    const std::uint32_t count = k == 5 ? rows : rows - 1;
    Level l;
    for (std::uint32_t n = 0; n < count; ++n) {
      l.nodes.push_back(n * (rows + 1));  // the diagonal: one per row, increasing
      l.values.push_back(static_cast<float>(rng.Uniform(-0.1, 0.1)));
    }
    charts[1].push_back(l);
  }
  Status s;
  auto d = BsplineDisplacement::Create(Additive(charts, half), 2, &s);
  INFO(s.message());
  REQUIRE(d);
  for (int n = 0; n < 400; ++n) {
    // Half the points near the fine nodes (lattice coordinates 249..251, 199; 9, 299).
    Vec2 z(rng.Uniform(-1.1, 1.1), rng.Uniform(-1.1, 1.1));
    if (n % 2 == 0) {
      const double cell = 2.0 * half / 512.0;
      const bool first = n % 4 == 0;
      z = Vec2(-half + cell * ((first ? 250.0 : 9.0) + rng.Uniform(-2.0, 2.0)),
               -half + cell * ((first ? 199.0 : 299.0) + rng.Uniform(-2.0, 2.0)));
    }
    for (std::size_t c = 0; c < charts.size(); ++c) {
      double expected = 0.0;
      for (std::size_t k = 0; k < charts[c].size(); ++k) {
        expected +=
            BruteLevel(charts[c][k].nodes, charts[c][k].values, static_cast<int>(k), half, z);
      }
      double v = 0.0;
      Vec2 g;
      d->Evaluate(static_cast<Index>(c), z, &v, &g);
      CHECK(v == Approx(expected).margin(1e-12));
    }
  }
  // The fine level costs its nodes, values, per-level entries and the arrays' growth (about
  // 100 bytes with libstdc++), not a row table (2,064 bytes, about 3.5 KB with its growth).
  std::vector<std::vector<Level>> coarse = charts;
  coarse[0].pop_back();
  auto dc = BsplineDisplacement::Create(Additive(coarse, half), 2, &s);
  REQUIRE(dc);
  const std::size_t extra = d->memory_bytes() - dc->memory_bytes();
  INFO("bytes for the 3-node level 9: " << extra);
  CHECK(extra < 1000);
}

TEST_CASE("displacement: invalid additive data is rejected with a reason", "[displacement]") {
  test::Lcg rng(2);
  const BsplineDisplacementData good = Additive({RandomLevels(3, 0.5, &rng)}, 1.0);
  Status s;
  REQUIRE(BsplineDisplacement::Create(good, 1, &s));
  auto expect_error = [&](BsplineDisplacementData d, const char* what) {
    INFO(what);
    CHECK_FALSE(BsplineDisplacement::Create(std::move(d), 1, &s));
    CHECK(s.code() == StatusCode::kInvalidInput);
    CHECK(s.message().find("displacement") != std::string::npos);
  };
  BsplineDisplacementData d = good;
  d.level_counts.pop_back();
  expect_error(d, "missing level count");
  d = good;
  d.level_counts[0] = 17;  // more than the 16 nodes of level 0
  expect_error(d, "count above the lattice size");
  d = good;
  std::swap(d.nodes[0], d.nodes[1]);
  expect_error(d, "nodes not increasing");
  d = good;
  d.nodes.back() = 1000;  // outside the 7 x 7 lattice of level 2
  expect_error(d, "node out of range");
  d = good;
  d.nodes.push_back(5);
  expect_error(d, "a node list too long");
  d = good;
  d.offsets[1] -= 1;
  expect_error(d, "offsets not matching the counts");
  d = good;
  d.form = BsplineLevelForm::kMerged;  // merged lattices have no node lists
  expect_error(d, "merged form with node lists");
}

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/offline/fit/shading_check.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "dermis/offline/build/domain_builder.h"
#include "dermis/surface/surface_evaluator.h"

using namespace dermis;

namespace {

// A uniform number in [-0.5, 0.5) from a fixed recurrence.
struct Numbers {
  std::uint64_t state = 777;
  float Next() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<float>(static_cast<double>(state >> 11) / 9007199254740992.0 - 0.5);
  }
};

// Additive data over `charts` charts: chart c gets levels[c] levels; level k is dense for
// k < 2, sparse (every fifth node) from 2 on, and empty (no node) where empty[c] == k.
BsplineDisplacementData Data(const std::vector<int>& levels, const std::vector<int>& empty,
                             float scale) {
  BsplineDisplacementData d;
  d.form = BsplineLevelForm::kAdditive;
  Numbers r;
  for (std::size_t c = 0; c < levels.size(); ++c) {
    d.half_extent.push_back(1.3);
    d.num_levels.push_back(static_cast<std::uint8_t>(levels[c]));
    d.offsets.push_back(static_cast<std::int64_t>(d.values.size()));
    for (int k = 0; k < levels[c]; ++k) {
      const std::int64_t size = BsplineLatticeSize(k);
      if (empty[c] == k) {
        d.level_counts.push_back(0);
      } else if (k < 2) {
        d.level_counts.push_back(static_cast<std::int32_t>(size));
        for (std::int64_t n = 0; n < size; ++n) d.values.push_back(scale * r.Next());
      } else {
        std::int32_t count = 0;
        for (std::int64_t n = 0; n < size; n += 5, ++count) {
          d.nodes.push_back(static_cast<std::uint32_t>(n));
          d.values.push_back(scale * r.Next());
        }
        d.level_counts.push_back(count);
      }
    }
  }
  d.offsets.push_back(static_cast<std::int64_t>(d.values.size()));
  return d;
}

// A 4 x 4 grid of unit quads in z = 0: its domain surface is that plane.
PolygonMesh Sheet() {
  PolygonMesh m;
  m.source_name = "sheet";
  for (int j = 0; j <= 4; ++j)
    for (int i = 0; i <= 4; ++i) m.positions.push_back({double(i), double(j), 0.0});
  auto id = [](int i, int j) { return static_cast<Index>(j * 5 + i); };
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) m.AddFace({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return m;
}

}  // namespace

TEST_CASE("shading check: a truncated displacement is the first levels of the original") {
  // Chart 0: 4 levels; 1: 2; 2: none; 3: 3 levels whose level 1 is empty; 4: 5 levels.
  const std::vector<int> levels = {4, 2, 0, 3, 5}, empty = {-1, -1, -1, 1, -1};
  const BsplineDisplacementData full = Data(levels, empty, 0.01f);
  const std::int64_t nc = static_cast<std::int64_t>(levels.size());
  Status s;
  const auto original = BsplineDisplacement::Create(full, nc, &s);
  REQUIRE(original);
  for (int keep = 0; keep <= 3; ++keep) {
    const BsplineDisplacementData cut = TruncateBsplineLevels(full, keep);
    REQUIRE(ValidateBsplineDisplacementData(cut, nc).ok());
    const auto truncated = BsplineDisplacement::Create(cut, nc, &s);
    REQUIRE(truncated);
    // Each chart keeps min(levels, keep), less its trailing empty levels (chart 3 at 2: one).
    for (std::size_t c = 0; c < levels.size(); ++c) {
      int expect = std::min(levels[c], keep);
      if (c == 3 && expect == 2) expect = 1;
      CHECK(static_cast<int>(cut.num_levels[c]) == expect);
    }
    CHECK(truncated->max_levels() == keep);
    std::int64_t coefficients = 0;
    for (int k = 0; k < keep; ++k) coefficients += original->level_coefficients(k);
    CHECK(truncated->num_coefficients() == coefficients);
    // The same function as the original evaluated with `keep` levels, value and gradient.
    Numbers r;
    for (Index c = 0; c < static_cast<Index>(nc); ++c) {
      for (int i = 0; i < 50; ++i) {
        const Vec2 z(2.6 * r.Next(), 2.6 * r.Next());
        double a = 0.0, b = 0.0;
        Vec2 ga(0.0), gb(0.0);
        original->EvaluateLevels(c, z, keep, &a, &ga);
        truncated->Evaluate(c, z, &b, &gb);
        CHECK(b == Approx(a).margin(1e-15));
        CHECK(gb.x == Approx(ga.x).margin(1e-14));
        CHECK(gb.y == Approx(ga.y).margin(1e-14));
      }
    }
  }
  // As many levels as the deepest chart, or more: the data unchanged.
  for (int keep : {5, 9}) {
    const BsplineDisplacementData same = TruncateBsplineLevels(full, keep);
    CHECK(same.num_levels == full.num_levels);
    CHECK(same.values == full.values);
    CHECK(same.nodes == full.nodes);
    CHECK(same.level_counts == full.level_counts);
  }
  // The merged form is returned as it is.
  BsplineDisplacementData merged;
  merged.form = BsplineLevelForm::kMerged;
  merged.half_extent = {1.0};
  merged.num_levels = {2};
  merged.offsets = {0, BsplineLatticeSize(1)};
  merged.values.assign(static_cast<std::size_t>(BsplineLatticeSize(1)), 0.5f);
  const BsplineDisplacementData m = TruncateBsplineLevels(merged, 1);
  CHECK(m.num_levels == merged.num_levels);
  CHECK(m.values == merged.values);
}

TEST_CASE("shading check: trailing levels are dropped while they turn the normals away") {
  CHECK(ShadingCheckLevels({}, 0.0) == 0);
  CHECK(ShadingCheckLevels({3.0}, 0.0) == 0);
  // 5 -> 4.7 helps; 4.73 and 4.8 each turn the normals away: keep 1.
  CHECK(ShadingCheckLevels({5.0, 4.7, 4.73, 4.8}, 0.0) == 1);
  // With a tolerance of 1 %: 4.73 is within it of 4.7 and stays; 4.8 is 1.5 % worse.
  CHECK(ShadingCheckLevels({5.0, 4.7, 4.73, 4.8}, 0.01) == 2);
  // A level that makes them worse before a finer one brings them back is kept: the rule
  // looks at the trailing levels only.
  CHECK(ShadingCheckLevels({5.0, 5.2, 4.6}, 0.0) == 2);
  // Equal is not worse.
  CHECK(ShadingCheckLevels({2.0, 1.0, 1.0}, 0.0) == 2);
  // Every level worse: none kept.
  CHECK(ShadingCheckLevels({1.0, 1.1, 1.2}, 0.0) == 0);
}

TEST_CASE("shading check: the angles against the shading normals, level by level") {
  ControlSurface cs;
  REQUIRE(BuildControlSurface(Sheet(), DomainOptions{}, &cs).ok());
  const ManifoldDomain& domain = *cs.domain;
  const Index nv = domain.num_vertices();
  // Level 0 of every chart a constant 0.05 (its B-spline sums to it: the plane moves along
  // its normal, which stays z); level 1 random, which tilts it.
  BsplineDisplacementData d;
  d.form = BsplineLevelForm::kAdditive;
  Numbers r;
  for (Index c = 0; c < nv; ++c) {
    d.half_extent.push_back(1.3);
    d.num_levels.push_back(2);
    d.offsets.push_back(static_cast<std::int64_t>(d.values.size()));
    d.level_counts.push_back(static_cast<std::int32_t>(BsplineLatticeSize(0)));
    for (std::int64_t n = 0; n < BsplineLatticeSize(0); ++n) d.values.push_back(0.05f);
    d.level_counts.push_back(static_cast<std::int32_t>(BsplineLatticeSize(1)));
    for (std::int64_t n = 0; n < BsplineLatticeSize(1); ++n) d.values.push_back(0.2f * r.Next());
  }
  d.offsets.push_back(static_cast<std::int64_t>(d.values.size()));
  Status s;
  const auto disp = BsplineDisplacement::Create(d, nv, &s);
  REQUIRE(disp);
  // Check points at the faces' (0.3, 0.6), the source's normals 0.2 rad from z, every other
  // one negated (the angle is between lines).
  const double theta = 0.2;
  std::vector<PointFit> fits;
  std::vector<Vec3> normals;
  for (Index f = 0; f < domain.num_faces(); ++f) {
    PointFit p;
    p.status = PointFitStatus::kOptimized;
    p.face = f;
    p.uv = Vec2(0.3, 0.6);
    fits.push_back(p);
    const double sign = f % 2 == 0 ? 1.0 : -1.0;
    normals.push_back(sign * Vec3(std::sin(theta), 0.0, std::cos(theta)));
  }
  // Left out: a point outside and one the optimisation did not converge at (valid
  // parameters, normals 90 degrees off), and one without a normal.
  PointFit outside = fits[1];
  outside.status = PointFitStatus::kOutside;
  fits.push_back(outside);
  normals.push_back(Vec3(1.0, 0.0, 0.0));
  PointFit lost = fits[2];
  lost.status = PointFitStatus::kNotConverged;
  fits.push_back(lost);
  normals.push_back(Vec3(1.0, 0.0, 0.0));
  fits.push_back(fits[0]);
  normals.push_back(Vec3(0.0));
  const std::vector<double> angles =
      CheckPointNormalAngles(domain, cs.patches.data(), *disp, fits, normals, 2);
  REQUIRE(angles.size() == 3u);
  // No level and the constant level: the plane's normal, theta from every source normal.
  CHECK(angles[0] == Approx(theta).epsilon(1e-9));
  CHECK(angles[1] == Approx(theta).epsilon(1e-6));
  // Both levels: the displaced surface's normal from its positions (central differences of
  // EvaluateSurface's positions, not its normal), against each source normal.
  const TruncatedDisplacement both(disp.get(), 2);
  double sum = 0.0;
  for (Index f = 0; f < domain.num_faces(); ++f) {
    const double h = 1e-5;
    SurfacePoint pu0, pu1, pv0, pv1;
    REQUIRE(EvaluateSurface(domain, cs.patches.data(), &both, f, Vec2(0.3 - h, 0.6), &pu0));
    REQUIRE(EvaluateSurface(domain, cs.patches.data(), &both, f, Vec2(0.3 + h, 0.6), &pu1));
    REQUIRE(EvaluateSurface(domain, cs.patches.data(), &both, f, Vec2(0.3, 0.6 - h), &pv0));
    REQUIRE(EvaluateSurface(domain, cs.patches.data(), &both, f, Vec2(0.3, 0.6 + h), &pv1));
    const Vec3 n =
        glm::normalize(glm::cross(pu1.position - pu0.position, pv1.position - pv0.position));
    const Vec3& m = normals[static_cast<std::size_t>(f)];
    sum += std::acos(std::min(1.0, std::abs(glm::dot(n, m))));
  }
  const double expect = sum / static_cast<double>(domain.num_faces());
  CHECK(expect != Approx(theta).epsilon(1e-3));  // the random level does tilt it
  CHECK(angles[2] == Approx(expect).epsilon(1e-5));
  // The same whatever the thread count.
  CHECK(CheckPointNormalAngles(domain, cs.patches.data(), *disp, fits, normals, 1) == angles);
  // No point with a normal: every entry 0.
  const std::vector<double> none = CheckPointNormalAngles(
      domain, cs.patches.data(), *disp, fits, std::vector<Vec3>(fits.size(), Vec3(0.0)), 2);
  CHECK(none == std::vector<double>(3, 0.0));
}

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/surface/blend.h"

#include <catch2/catch.hpp>

#include "dermis/surface/chart.h"
#include "support/domains.h"

using namespace dermis;

TEST_CASE("C-infinity step matches the reference values of docs/notes/manifold.md section 4",
          "[blend]") {
  const double t[5] = {0.1, 0.25, 0.5, 0.75, 0.9};
  const double ref[5] = {0.998619, 0.886948, 0.5, 0.113052, 0.001381};
  for (int i = 0; i < 5; ++i)
    CHECK(BlendStep(BlendType::kCInfinity, t[i]) == Approx(ref[i]).margin(1e-6));
  CHECK(BlendStep(BlendType::kC2, 0.25) == Approx(0.9296875).margin(1e-12));
  CHECK(BlendStep(BlendType::kC2, 0.5) == Approx(0.5).margin(1e-15));
}

TEST_CASE("steps are 1 below 0, 0 above 1 and satisfy beta(t) + beta(1-t) = 1", "[blend]") {
  for (BlendType type : {BlendType::kCInfinity, BlendType::kC2}) {
    CHECK(BlendStep(type, -0.3) == 1.0);
    CHECK(BlendStep(type, 0.0) == 1.0);
    CHECK(BlendStep(type, 1.0) == 0.0);
    CHECK(BlendStep(type, 1.7) == 0.0);
    for (int i = 0; i <= 1000; ++i) {
      const double t = i / 1000.0;
      REQUIRE(BlendStep(type, t) + BlendStep(type, 1.0 - t) == Approx(1.0).margin(1e-15));
    }
  }
}

TEST_CASE("steps are exact and finite right next to 0 and 1", "[blend]") {
  // 1 - t rounds to 1 for these t: the step must still be ~1 (and ~0 mirrored), never NaN.
  for (double t : {1e-300, 5e-324, 1e-17, 9e-18, 1e-10, 1e-4}) {
    for (BlendType type : {BlendType::kCInfinity, BlendType::kC2}) {
      double d0 = 0.0, d1 = 0.0;
      CHECK(BlendStep(type, t, &d0) == Approx(1.0).margin(1e-9));
      CHECK(BlendStep(type, 1.0 - t, &d1) == Approx(0.0).margin(1e-9));
      CHECK(std::isfinite(d0));
      CHECK(std::isfinite(d1));
    }
  }
}

TEST_CASE("step derivatives match central differences", "[blend]") {
  for (BlendType type : {BlendType::kCInfinity, BlendType::kC2}) {
    for (int i = 1; i < 200; ++i) {
      const double t = i / 200.0, h = 1e-6;
      double d = 0.0;
      BlendStep(type, t, &d);
      const double fd = (BlendStep(type, t + h) - BlendStep(type, t - h)) / (2 * h);
      REQUIRE(d == Approx(fd).margin(1e-7));
    }
  }
}

TEST_CASE("the four corner weights of a face sum to one", "[blend]") {
  test::Lcg rng(7);
  for (BlendType type : {BlendType::kCInfinity, BlendType::kC2}) {
    for (double lb : {0.125, 0.05, 0.3}) {
      for (int i = 0; i < 2000; ++i) {
        const double s = rng.Next(), t = rng.Next();
        // Corner coordinates of the 4 corners (docs/notes/manifold.md section 0).
        const Vec2 cd[4] = {{s, t}, {t, 1 - s}, {1 - s, 1 - t}, {1 - t, s}};
        double sum = 0.0;
        Vec2 gsum(0.0);
        for (int a = 0; a < 4; ++a) {
          Vec2 g;
          sum += CornerWeight(type, lb, cd[a], &g);
          // Gradient w.r.t. (s, t): rotate back.
          const Vec2 gst = a == 0 ? g : a == 1 ? Vec2(-g.y, g.x) : a == 2 ? -g : Vec2(g.y, -g.x);
          gsum += gst;
        }
        REQUIRE(sum == Approx(1.0).margin(1e-14));
        REQUIRE(std::abs(gsum.x) < 1e-9);
        REQUIRE(std::abs(gsum.y) < 1e-9);
      }
    }
  }
}

TEST_CASE("a face's four corner weights at once equal CornerWeight bit for bit", "[blend]") {
  // FaceCornerWeights evaluates the steps at u, 1 - u, v, 1 - v once each; the evaluator, the
  // projection and the control fit rely on it giving exactly CornerWeight's values.
  test::Lcg rng(11);
  for (BlendType type : {BlendType::kCInfinity, BlendType::kC2}) {
    for (double lb : {0.01, 0.125, 0.3}) {
      for (int i = 0; i < 2000; ++i) {
        // Random points, and points on the face's edges, corners and blend-window borders.
        Vec2 uv(rng.Next(), rng.Next());
        if (i % 7 == 0) uv.x = (i / 7) % 3 == 0 ? 0.0 : (i / 7) % 3 == 1 ? 1.0 : lb;
        if (i % 11 == 0) uv.y = (i / 11) % 2 == 0 ? 1.0 - lb : 0.5;
        double psi[4];
        Vec2 grad[4];
        FaceCornerWeights(type, lb, uv, psi, grad);
        double psi_only[4];
        FaceCornerWeights(type, lb, uv, psi_only);
        for (int a = 0; a < 4; ++a) {
          Vec2 g;
          const double w = CornerWeight(type, lb, FaceToCorner(a, uv), &g);
          INFO("corner " << a << " at (" << uv.x << ", " << uv.y << ")");
          REQUIRE(psi[a] == w);
          REQUIRE(psi_only[a] == w);
          REQUIRE(grad[a].x == g.x);
          REQUIRE(grad[a].y == g.y);
        }
      }
    }
  }
}

TEST_CASE("corner weight is 1 on [0,lb]^2 and 0 once c or d reaches ub", "[blend]") {
  const double lb = 0.125;
  CHECK(CornerWeight(BlendType::kCInfinity, lb, {0.0, 0.0}) == 1.0);
  CHECK(CornerWeight(BlendType::kCInfinity, lb, {0.1, 0.125}) == 1.0);
  CHECK(CornerWeight(BlendType::kCInfinity, lb, {0.875, 0.0}) == 0.0);
  CHECK(CornerWeight(BlendType::kCInfinity, lb, {0.2, 0.95}) == 0.0);
  const double mid = CornerWeight(BlendType::kCInfinity, lb, {0.5, 0.5});
  CHECK(mid == Approx(0.25).margin(1e-15));
}

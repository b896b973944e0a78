// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/offline/geometry/mesh_metrics.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <vector>

using namespace dermis;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A cube of side `a` whose faces have their own 4 vertices each (split seams, as a renderer's
// flat-shaded mesh), two triangles per face, outward.
void SplitCube(double a, std::vector<Vec3>* x, std::vector<std::uint32_t>* t) {
  const int faces[6][4][3] = {
      {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}, {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
      {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}, {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}},
      {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}, {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}};
  for (const auto& f : faces) {
    const auto base = static_cast<std::uint32_t>(x->size());
    for (const auto& c : f) x->push_back(a * Vec3(c[0], c[1], c[2]));
    for (std::uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) t->push_back(base + k);
  }
}

}  // namespace

TEST_CASE("mesh metrics: the integral of |mean curvature| of a cube, a prism and a plane") {
  // A cube: 12 edges of length a, each turning by pi/2, half of it counted: 3 pi a. The
  // faces' diagonals are flat. Its split seams are welded.
  for (double a : {1.0, 2.5}) {
    std::vector<Vec3> x;
    std::vector<std::uint32_t> t;
    SplitCube(a, &x, &t);
    CHECK(AbsMeanCurvatureIntegral(x, t, 1e-9) == Approx(3.0 * kPi * a).epsilon(1e-12));
  }
  // An open prism of n sides round a circle of radius r, height h: n vertical edges of length
  // h each turning by 2 pi / n, so pi h whatever n and r (a cylinder's |H| = 1 / (2r) over
  // its area 2 pi r h). Its boundary edges have one triangle and do not count.
  for (int n : {5, 12, 40}) {
    for (double r : {0.5, 3.0}) {
      const double h = 1.7;
      std::vector<Vec3> x;
      std::vector<std::uint32_t> t;
      for (int i = 0; i < n; ++i) {
        const double a = 2.0 * kPi * i / n;
        x.push_back({r * std::cos(a), r * std::sin(a), 0.0});
        x.push_back({r * std::cos(a), r * std::sin(a), h});
      }
      for (int i = 0; i < n; ++i) {
        const auto b0 = static_cast<std::uint32_t>(2 * i),
                   b1 = static_cast<std::uint32_t>(2 * ((i + 1) % n));
        for (std::uint32_t k : {b0, b1, b1 + 1, b0, b1 + 1, b0 + 1}) t.push_back(k);
      }
      CHECK(AbsMeanCurvatureIntegral(x, t, 1e-9) == Approx(kPi * h).epsilon(1e-12));
    }
  }
  // A flat grid, a lone triangle and a degenerate one: nothing bends.
  std::vector<Vec3> x;
  std::vector<std::uint32_t> t;
  for (int j = 0; j <= 3; ++j)
    for (int i = 0; i <= 3; ++i) x.push_back({double(i), double(j), 0.0});
  for (std::uint32_t j = 0; j < 3; ++j) {
    for (std::uint32_t i = 0; i < 3; ++i) {
      const std::uint32_t v = 4 * j + i;
      for (std::uint32_t k : {v, v + 1, v + 5, v, v + 5, v + 4}) t.push_back(k);
    }
  }
  CHECK(AbsMeanCurvatureIntegral(x, t, 1e-9) == 0.0);
  CHECK(AbsMeanCurvatureIntegral(x, {0, 1, 4}, 1e-9) == 0.0);
  CHECK(AbsMeanCurvatureIntegral(x, {0, 1, 4, 0, 0, 1}, 1e-9) == 0.0);
}

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/offline/geometry/triangle_distance.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "test_meshes.h"

using namespace dermis;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

double MaxAbs(const Vec3& v) {
  return std::max(std::abs(v.x), std::max(std::abs(v.y), std::abs(v.z)));
}

struct Expect {
  Vec3 p;
  Vec3 point;
  Vec3 barycentric;
  double distance;
};

/// Checks ClosestPointOnTriangle against `cases` for the triangle (a, b, c) mapped by
/// x -> R x + t, which must not change the answer beyond rounding: `tol` for the distance,
/// `point_tol` for the point and (if `check_bary`) the barycentric coordinates.
void CheckRigid(const std::vector<Expect>& cases, const Vec3& a, const Vec3& b, const Vec3& c,
                double angle, const Vec3& t, double tol, double point_tol, bool check_bary) {
  const Vec3 axis = glm::normalize(Vec3(1.0, 2.0, 3.0));
  auto map = [&](const Vec3& x) {  // Rodrigues rotation about `axis`, then translation.
    const double cs = std::cos(angle), sn = std::sin(angle);
    return x * cs + glm::cross(axis, x) * sn + axis * glm::dot(axis, x) * (1.0 - cs) + t;
  };
  for (const Expect& e : cases) {
    INFO("p = (" << e.p.x << ", " << e.p.y << ", " << e.p.z << "), angle " << angle);
    Vec3 bary(-1.0);
    const Vec3 q = ClosestPointOnTriangle(map(e.p), map(a), map(b), map(c), &bary);
    CHECK(glm::length(map(e.p) - q) == Approx(e.distance).margin(tol));
    CHECK(MaxAbs(q - map(e.point)) < point_tol);
    if (check_bary) CHECK(MaxAbs(bary - e.barycentric) < point_tol);
    CHECK(MaxAbs(bary.x * map(a) + bary.y * map(b) + bary.z * map(c) - q) < point_tol);
    // Without the optional output the point is the same.
    CHECK(ClosestPointOnTriangle(map(e.p), map(a), map(b), map(c), nullptr) == q);
  }
}

/// A sphere-ish latitude/longitude grid of radius ~1 with random radial noise. The pole rows
/// hold coincident vertices, so the mesh includes degenerate (zero-area) triangles.
void NoisySphere(int n_lon, int n_lat, std::uint64_t seed, std::vector<Vec3>* positions,
                 std::vector<std::uint32_t>* triangles) {
  test::Lcg rng(seed);
  positions->clear();
  triangles->clear();
  for (int j = 0; j <= n_lat; ++j) {
    const double theta = kPi * j / n_lat;
    for (int i = 0; i < n_lon; ++i) {
      const double phi = 2.0 * kPi * i / n_lon;
      const double r = 1.0 + 0.1 * (rng.Next() - 0.5);
      const double r_pole = (j == 0 || j == n_lat) ? 1.0 : r;
      positions->push_back(r_pole * Vec3(std::sin(theta) * std::cos(phi),
                                         std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  }
  auto id = [n_lon](int i, int j) { return static_cast<std::uint32_t>(j * n_lon + i % n_lon); };
  for (int j = 0; j < n_lat; ++j) {
    for (int i = 0; i < n_lon; ++i) {
      triangles->insert(triangles->end(), {id(i, j), id(i, j + 1), id(i + 1, j + 1)});
      triangles->insert(triangles->end(), {id(i, j), id(i + 1, j + 1), id(i + 1, j)});
    }
  }
}

/// Brute force over all triangles; the first (lowest index) of equally close triangles wins.
ClosestPoint BruteForce(const std::vector<Vec3>& positions,
                        const std::vector<std::uint32_t>& triangles, const Vec3& p) {
  ClosestPoint best;
  best.distance = kInf;
  double best_d2 = kInf;
  for (std::size_t t = 0; t < triangles.size() / 3; ++t) {
    Vec3 bary;
    const Vec3 q =
        ClosestPointOnTriangle(p, positions[triangles[3 * t]], positions[triangles[3 * t + 1]],
                               positions[triangles[3 * t + 2]], &bary);
    const double d2 = glm::dot(p - q, p - q);
    if (d2 < best_d2) {
      best_d2 = d2;
      best.distance = std::sqrt(d2);
      best.point = q;
      best.triangle = static_cast<Index>(t);
      best.barycentric = bary;
    }
  }
  return best;
}

}  // namespace

TEST_CASE("triangle distance: closest point in each Voronoi region", "[triangle_distance]") {
  // Right triangle in the z = 0 plane; the hypotenuse bc is the line x + y = 2.
  const Vec3 a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  const std::vector<Expect> cases = {
      // Vertex regions.
      {{-1, -1, 3}, {0, 0, 0}, {1, 0, 0}, std::sqrt(11.0)},
      {{3, -1, -2}, {2, 0, 0}, {0, 1, 0}, std::sqrt(6.0)},
      {{-1, 3, 1}, {0, 2, 0}, {0, 0, 1}, std::sqrt(3.0)},
      // Edge regions.
      {{0.5, -2, 1}, {0.5, 0, 0}, {0.75, 0.25, 0}, std::sqrt(5.0)},
      {{-3, 1.5, -4}, {0, 1.5, 0}, {0.25, 0, 0.75}, 5.0},
      {{2, 2, 1}, {1, 1, 0}, {0, 0.5, 0.5}, std::sqrt(3.0)},
      {{2.5, 1.5, 0}, {1.5, 0.5, 0}, {0, 0.75, 0.25}, std::sqrt(2.0)},
      // Face region, both sides, and on the triangle.
      {{0.5, 0.5, -2}, {0.5, 0.5, 0}, {0.5, 0.25, 0.25}, 2.0},
      {{0.2, 1.2, 0.7}, {0.2, 1.2, 0}, {0.3, 0.1, 0.6}, 0.7},
      {{0.5, 1, 0}, {0.5, 1, 0}, {0.25, 0.25, 0.5}, 0.0},
      // Boundaries between regions.
      {{2, -1, 0}, {2, 0, 0}, {0, 1, 0}, 1.0},
      {{1, 0, 5}, {1, 0, 0}, {0.5, 0.5, 0}, 5.0},
  };
  CheckRigid(cases, a, b, c, 0.0, Vec3(0.0), 1e-14, 1e-14, true);
  CheckRigid(cases, a, b, c, 0.7, Vec3(3, -2, 1), 1e-13, 1e-13, true);
  CheckRigid(cases, a, b, c, 2.9, Vec3(-100, 50, 20), 1e-12, 1e-12, true);
}

TEST_CASE("triangle distance: thin triangles stay exact", "[triangle_distance]") {
  // Height 1e-9 over its longest edge ab: too thin for the region tests, not degenerate.
  const double h = 1e-9;
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0.5, h, 0);
  const std::vector<Expect> cases = {
      {{0.5, 0.5 * h, 1}, {0.5, 0.5 * h, 0}, {0.25, 0.25, 0.5}, 1.0},
      {{0.5, 0.5 * h, -3}, {0.5, 0.5 * h, 0}, {0.25, 0.25, 0.5}, 3.0},
      {{0.5, -1, 0}, {0.5, 0, 0}, {0.5, 0.5, 0}, 1.0},
      {{-2, 0, 0}, {0, 0, 0}, {1, 0, 0}, 2.0},
      {{0.5, 7, 0}, {0.5, h, 0}, {0, 0, 1}, 7.0 - h},
  };
  CheckRigid(cases, a, b, c, 0.0, Vec3(0.0), 1e-14, 1e-14, true);
  // Rotated, the corners are rounded by ~1e-15, which tilts the sliver's plane by ~1e-6 about
  // its long edge: the distance stays exact, the point moves by up to the height h across the
  // sliver, and the barycentric coordinates across it are ill-conditioned.
  CheckRigid(cases, a, b, c, 1.3, Vec3(1, 2, 3), 1e-13, 2 * h, false);

  // A very flat triangle (a sliver cap) seen from just above its interior: distance = height.
  for (double height : {1e-3, 1e-6, 1e-12}) {
    INFO("height " << height);
    const Vec3 p(0.3, 0.2 * height, 1e-4);
    Vec3 bary;
    const Vec3 q =
        ClosestPointOnTriangle(p, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.4, height, 0), &bary);
    CHECK(glm::length(p - q) == Approx(1e-4).epsilon(1e-12));
    CHECK(bary.x >= 0.0);
    CHECK(bary.y >= 0.0);
    CHECK(bary.z >= 0.0);
    CHECK(bary.x + bary.y + bary.z == Approx(1.0).epsilon(1e-14));
  }
}

TEST_CASE("triangle distance: degenerate triangles use their edges", "[triangle_distance]") {
  struct Case {
    Vec3 a, b, c, p, point;
    double distance;
  };
  const std::vector<Case> cases = {
      // Collinear, c beyond b.
      {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1.5, 1, 0}, {1.5, 0, 0}, 1.0},
      {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 1}, {2, 0, 0}, std::sqrt(2.0)},
      {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {-1, 0, 0}, {0, 0, 0}, 1.0},
      // Collinear, c between a and b.
      {{0, 0, 0}, {2, 0, 0}, {1, 0, 0}, {1.5, 0, -3}, {1.5, 0, 0}, 3.0},
      {{0, 0, 0}, {2, 0, 0}, {1, 0, 0}, {2.5, 0, 0}, {2, 0, 0}, 0.5},
      // Two coincident corners: a segment.
      {{0, 0, 0}, {0, 0, 0}, {0, 2, 0}, {1, 1, 0}, {0, 1, 0}, 1.0},
      {{0, 0, 0}, {0, 2, 0}, {0, 2, 0}, {0, 3, 4}, {0, 2, 0}, std::sqrt(17.0)},
      // All corners coincident: a point.
      {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {2, 3, 3}, {1, 1, 1}, 3.0},
      // Collinear along a skew direction.
      {{1, 1, 1}, {3, 3, 3}, {2, 2, 2}, {2, 2, 5}, {3, 3, 3}, std::sqrt(6.0)},
  };
  for (const Case& e : cases) {
    INFO("p = (" << e.p.x << ", " << e.p.y << ", " << e.p.z << ")");
    Vec3 bary(-1.0);
    const Vec3 q = ClosestPointOnTriangle(e.p, e.a, e.b, e.c, &bary);
    CHECK(glm::length(e.p - q) == Approx(e.distance).margin(1e-14));
    CHECK(MaxAbs(q - e.point) < 1e-14);
    CHECK(bary.x >= 0.0);
    CHECK(bary.y >= 0.0);
    CHECK(bary.z >= 0.0);
    CHECK(bary.x + bary.y + bary.z == Approx(1.0).epsilon(1e-15));
    CHECK(MaxAbs(bary.x * e.a + bary.y * e.b + bary.z * e.c - q) < 1e-14);
  }
}

TEST_CASE("triangle distance: tree matches brute force on a random mesh", "[triangle_distance]") {
  std::vector<Vec3> positions;
  std::vector<std::uint32_t> triangles;
  NoisySphere(40, 25, 7, &positions, &triangles);
  REQUIRE(triangles.size() == 3 * 2000);

  TriangleDistanceTree tree;
  REQUIRE(tree.Build(positions, triangles));
  CHECK(tree.num_triangles() == 2000);
  TriangleDistanceTree again;  // A second build must answer identically.
  REQUIRE(again.Build(positions, triangles));

  test::Lcg rng(12345);
  auto uniform = [&rng](double lo, double hi) { return lo + (hi - lo) * rng.Next(); };
  int far_count = 0;
  for (int k = 0; k < 1000; ++k) {
    Vec3 p;
    if (k % 2 == 0) {  // Near the surface: a random point on a random triangle, offset.
      const std::size_t t = static_cast<std::size_t>(rng.Next() * 2000);
      const double u = rng.Next(), v = rng.Next() * (1.0 - u);
      p = (1.0 - u - v) * positions[triangles[3 * t]] + u * positions[triangles[3 * t + 1]] +
          v * positions[triangles[3 * t + 2]];
      p += 0.05 * Vec3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    } else if (k % 4 == 1) {  // Far away.
      p = Vec3(uniform(-4, 4), uniform(-4, 4), uniform(-4, 4));
      ++far_count;
    } else {  // Inside, near the centre.
      p = Vec3(uniform(-0.5, 0.5), uniform(-0.5, 0.5), uniform(-0.5, 0.5));
    }
    if (k == 998) p = positions[0] + Vec3(0, 0, 0.5);  // Above the pole: many exact ties.
    if (k == 999) p = positions[100];                  // On a vertex: distance 0, ties.
    INFO("query " << k << " p = (" << p.x << ", " << p.y << ", " << p.z << ")");

    const ClosestPoint expect = BruteForce(positions, triangles, p);
    const ClosestPoint got = tree.Query(p);
    CHECK(got.distance == Approx(expect.distance).epsilon(1e-12).margin(1e-300));
    // The traversal is exact and breaks ties by index, so it finds the very same triangle.
    CHECK(got.triangle == expect.triangle);
    CHECK(MaxAbs(got.point - expect.point) <= 1e-12);
    CHECK(MaxAbs(got.barycentric - expect.barycentric) <= 1e-12);

    const ClosestPoint repeat = again.Query(p);
    CHECK(repeat.triangle == got.triangle);
    CHECK(repeat.distance == got.distance);

    // A bound just above the answer changes nothing; one below it finds nothing.
    const ClosestPoint bounded = tree.Query(p, expect.distance * (1.0 + 1e-9) + 1e-300);
    CHECK(bounded.triangle == expect.triangle);
    CHECK(bounded.distance == got.distance);
    if (expect.distance > 0.0) {
      const ClosestPoint none = tree.Query(p, expect.distance * (1.0 - 1e-9));
      CHECK(none.distance == kInf);
      CHECK(none.triangle == kInvalidIndex);
    }
  }
  CHECK(far_count == 250);
}

TEST_CASE("triangle distance: exact ties prefer the lower triangle index", "[triangle_distance]") {
  // The same grid twice: every query has an exact tie between triangle t and t + n.
  std::vector<Vec3> positions;
  std::vector<std::uint32_t> triangles;
  NoisySphere(12, 8, 3, &positions, &triangles);
  const std::size_t n = triangles.size() / 3;
  std::vector<std::uint32_t> doubled = triangles;
  doubled.insert(doubled.end(), triangles.begin(), triangles.end());
  TriangleDistanceTree tree;
  REQUIRE(tree.Build(positions, doubled));
  test::Lcg rng(99);
  for (int k = 0; k < 200; ++k) {
    const Vec3 p(4 * rng.Next() - 2, 4 * rng.Next() - 2, 4 * rng.Next() - 2);
    const ClosestPoint expect = BruteForce(positions, doubled, p);
    const ClosestPoint got = tree.Query(p);
    CHECK(got.triangle == expect.triangle);
    CHECK(got.distance == expect.distance);
    CHECK(static_cast<std::size_t>(got.triangle) < n);
  }
}

TEST_CASE("triangle distance: empty mesh gives infinity", "[triangle_distance]") {
  const TriangleDistanceTree unbuilt;
  CHECK(unbuilt.num_triangles() == 0);
  CHECK(unbuilt.Query(Vec3(1, 2, 3)).distance == kInf);

  TriangleDistanceTree tree;
  REQUIRE(tree.Build({}, {}));
  CHECK(tree.num_triangles() == 0);
  const ClosestPoint r = tree.Query(Vec3(0.0));
  CHECK(r.distance == kInf);
  CHECK(r.triangle == kInvalidIndex);

  REQUIRE(tree.Build({Vec3(0.0), Vec3(1.0)}, {}));  // Positions but no triangles.
  CHECK(tree.Query(Vec3(0.0), 10.0).distance == kInf);
}

TEST_CASE("triangle distance: Build rejects out-of-range indices", "[triangle_distance]") {
  const std::vector<Vec3> positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  TriangleDistanceTree tree;
  REQUIRE(tree.Build(positions, {0, 1, 2}));
  CHECK(tree.num_triangles() == 1);
  CHECK(tree.Query(Vec3(0, 0, 2)).distance == 2.0);

  CHECK_FALSE(tree.Build(positions, {0, 1, 3}));
  CHECK(tree.num_triangles() == 0);  // A failed build leaves the tree empty.
  CHECK(tree.Query(Vec3(0, 0, 2)).distance == kInf);
  CHECK_FALSE(tree.Build(positions, {0, 1, 2, 2, 1, 0xFFFFFFFFu}));
  CHECK_FALSE(tree.Build(positions, {0, 1}));  // Not a multiple of 3.
  CHECK_FALSE(tree.Build({}, {0, 0, 0}));
  // A used position that is not finite is rejected; an unused one is fine.
  CHECK_FALSE(tree.Build({{0, 0, 0}, {1, 0, 0}, {0, kInf, 0}}, {0, 1, 2}));
  CHECK(tree.Build({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {std::nan(""), 0, 0}}, {0, 1, 2}));
}

TEST_CASE("triangle distance: max_distance early-out", "[triangle_distance]") {
  const std::vector<Vec3> positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                       {5, 0, 0}, {6, 0, 0}, {5, 1, 0}};
  TriangleDistanceTree tree;
  REQUIRE(tree.Build(positions, {3, 4, 5, 0, 1, 2}));
  const Vec3 p(-2, 0, 0);  // Vertex region of corner (0, 0, 0), at distance exactly 2.

  const ClosestPoint full = tree.Query(p);
  CHECK(full.distance == 2.0);
  CHECK(full.triangle == 1);
  CHECK(full.point == Vec3(0.0));
  CHECK(full.barycentric == Vec3(1, 0, 0));

  CHECK(tree.Query(p, 3.0).distance == 2.0);
  CHECK(tree.Query(p, 2.0).distance == 2.0);  // A point exactly at the bound is found.
  const ClosestPoint none = tree.Query(p, 1.999);
  CHECK(none.distance == kInf);
  CHECK(none.triangle == kInvalidIndex);
  CHECK(tree.Query(p, 0.0).distance == kInf);
  CHECK(tree.Query(Vec3(0.5, 0.25, 0), 0.0).distance == 0.0);  // On the mesh: found with 0.
  CHECK(tree.Query(p, -1.0).distance == kInf);
  CHECK(tree.Query(p, std::nan("")).distance == kInf);
  // A bound that excludes only the nearer triangle finds nothing, never the farther one.
  CHECK(tree.Query(Vec3(8, 0, 0), 1.5).distance == kInf);
  CHECK(tree.Query(Vec3(8, 0, 0), 2.0).triangle == 0);
  // Non-finite query points find nothing.
  CHECK(tree.Query(Vec3(kInf, 0, 0)).distance == kInf);
  CHECK(tree.Query(Vec3(0, std::nan(""), 0)).triangle == kInvalidIndex);
}

TEST_CASE("triangle distance: fan triangulation of a polygon mesh", "[triangle_distance]") {
  PolygonMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}, {3, 0.5, 0}};
  mesh.AddFace({0, 1, 2, 3});
  mesh.AddFace({1, 4, 2});
  mesh.AddFace({4, 6, 5, 2, 1});
  const std::vector<std::uint32_t> triangles = TriangulateFan(mesh);
  CHECK(triangles ==
        std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 1, 4, 2, 4, 6, 5, 4, 5, 2, 4, 2, 1});
  CHECK(TriangulateFan(PolygonMesh{}).empty());

  TriangleDistanceTree tree;
  REQUIRE(tree.Build(mesh.positions, triangles));
  CHECK(tree.num_triangles() == 6);
  const ClosestPoint r = tree.Query(Vec3(0.25, 0.75, 1.0));
  CHECK(r.distance == Approx(1.0));
  CHECK(r.triangle == 1);
}

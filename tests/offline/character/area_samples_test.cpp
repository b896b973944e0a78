// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The samples a character part's fit adds on its triangles (sdk/src/offline/character/
// area_samples.h): about the spacing apart in every direction, slivers included.
#include "offline/character/area_samples.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "dermis/asset/polygon_mesh.h"
#include "dermis/offline/geometry/shading_surface.h"

namespace dermis {
namespace {

/// One triangle, its samples (flat: no normals) at `spacing`, no densifying at its boundary
/// edges (every edge of a lone triangle is one).
std::vector<Vec3> LoneTriangleSamples(const Vec3& a, const Vec3& b, const Vec3& c, double spacing,
                                      PolygonMesh* mesh) {
  mesh->positions = {a, b, c};
  mesh->AddFace({0, 1, 2});
  ShadingSurface flat;
  flat.Build(*mesh, {}, 0.0, 0.0);
  return character::AreaSamples(*mesh, flat, {}, spacing, 0.5, 1.0, false);
}

/// The smallest distance between two of the points.
double SmallestGap(const std::vector<Vec3>& points) {
  double gap = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (std::size_t j = i + 1; j < points.size(); ++j) {
      gap = std::min(gap, glm::length(points[i] - points[j]));
    }
  }
  return gap;
}

/// The largest distance from a point of the triangle (a 200 x 200 barycentric grid) to the
/// nearest of `points`.
double LargestHole(const Vec3& a, const Vec3& b, const Vec3& c, const std::vector<Vec3>& points) {
  double hole = 0.0;
  const int n = 200;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; i + j <= n; ++j) {
      const double s = double(i) / n, t = double(j) / n;
      const Vec3 x = (1.0 - s - t) * a + s * b + t * c;
      double nearest = std::numeric_limits<double>::infinity();
      for (const Vec3& p : points) nearest = std::min(nearest, glm::length(x - p));
      hole = std::max(hole, nearest);
    }
  }
  return hole;
}

}  // namespace

TEST_CASE("character samples: a sliver is sampled as far apart across as along") {
  // A 10 x 0.5 triangle at spacing 1: a barycentric grid of spacing 1 along its longest edge
  // (ten segments) put its 36 inner points 0.05 apart across it; its edges' samples alone are
  // about 1 apart, and every point of it is within about the spacing of one.
  const Vec3 a(0.0, 0.0, 0.0), b(10.0, 0.0, 0.0), c(4.0, 0.5, 0.0);
  PolygonMesh mesh;
  const std::vector<Vec3> samples = LoneTriangleSamples(a, b, c, 1.0, &mesh);
  // Edges of 10, 6.02 and 4.03: 9 + 6 + 4 points, none inside.
  CHECK(samples.size() == 19);
  for (const Vec3& p : samples) {
    CHECK(p.z == 0.0);
    CHECK(p.y >= 0.0);
    CHECK(p.y <= 0.5);
  }
  std::vector<Vec3> all = samples;
  all.insert(all.end(), mesh.positions.begin(), mesh.positions.end());
  // Measured 0.50: half the spacing along the longest edge.
  CHECK(LargestHole(a, b, c, all) < 0.6);
}

TEST_CASE("character samples: a wide sliver gets rows along its longest edge") {
  // 20 x 3 (a sliver: less than a quarter as high as long) at spacing 1: 3 rows, 1 apart,
  // parallel to the longest edge, inside; points about 1 apart on each.
  const Vec3 a(0.0, 0.0, 0.0), b(20.0, 0.0, 0.0), c(10.0, 3.0, 0.0);
  PolygonMesh mesh;
  const std::vector<Vec3> samples = LoneTriangleSamples(a, b, c, 1.0, &mesh);
  std::vector<double> heights;
  for (const Vec3& p : samples) {
    if (p.y > 1e-12) heights.push_back(p.y);
  }
  // Inside: the rows at heights 1 and 2 (13 and 6 points between the short edges); on the
  // short edges (10.44 long): 10 points each, at heights 3 k / 11.
  const auto at = [&](double y) {
    return std::count_if(samples.begin(), samples.end(),
                         [&](const Vec3& p) { return std::abs(p.y - y) < 1e-9; });
  };
  CHECK(at(0.0) == 19);  // the longest edge: 20 segments
  CHECK(at(1.0) == 13);
  CHECK(at(2.0) == 6);
  CHECK(samples.size() == 19 + 13 + 6 + 2 * 10);
  std::vector<Vec3> all = samples;
  all.insert(all.end(), mesh.positions.begin(), mesh.positions.end());
  // Measured 0.29 (the rows' ends and the short edges' samples, whose spacings differ) and
  // 0.67.
  CHECK(SmallestGap(all) > 0.25);
  CHECK(LargestHole(a, b, c, all) < 0.8);
}

TEST_CASE("character samples: a triangle that is no sliver keeps its barycentric grid") {
  // Equilateral, side 10, spacing 1: a grid of 10 segments per edge, its 36 inner points and 9
  // on each edge, all 1 apart.
  const Vec3 a(0.0, 0.0, 0.0), b(10.0, 0.0, 0.0), c(5.0, 5.0 * std::sqrt(3.0), 0.0);
  PolygonMesh mesh;
  const std::vector<Vec3> samples = LoneTriangleSamples(a, b, c, 1.0, &mesh);
  CHECK(samples.size() == 36 + 3 * 9);
  std::vector<Vec3> all = samples;
  all.insert(all.end(), mesh.positions.begin(), mesh.positions.end());
  CHECK(SmallestGap(all) == Approx(1.0).epsilon(1e-9));
  CHECK(LargestHole(a, b, c, all) < 0.6);  // 1 / sqrt(3): a lattice triangle's centre
}

}  // namespace dermis

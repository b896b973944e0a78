// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The samples a character part's fit adds on its triangles (sdk/src/offline/character/
// area_samples.h): about the spacing apart in every direction, slivers included.
#include "offline/character/area_samples.h"

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "dermis/asset/polygon_mesh.h"
#include "dermis/offline/geometry/shading_surface.h"

namespace dermis {
namespace {

/// One triangle, its samples (flat: no normals) at `spacing`; by default no densifying at its
/// boundary edges (every edge of a lone triangle is one) and no rows beside them.
std::vector<Vec3> LoneTriangleSamples(const Vec3& a, const Vec3& b, const Vec3& c, double spacing,
                                      PolygonMesh* mesh, double crease_factor = 1.0,
                                      bool crease_rows = false) {
  mesh->positions = {a, b, c};
  mesh->face_offsets = {0};
  mesh->face_vertices.clear();
  mesh->AddFace({0, 1, 2});
  ShadingSurface flat;
  flat.Build(*mesh, {}, 0.0, 0.0);
  return character::AreaSamples(*mesh, flat, {}, spacing, 0.5, crease_factor, crease_rows);
}

/// Barycentric weights of p in the triangle (a, b, c) of the plane z = 0.
std::array<double, 3> Weights(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
  const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  const double wa = ((b.x - p.x) * (c.y - p.y) - (b.y - p.y) * (c.x - p.x)) / area;
  const double wb = ((c.x - p.x) * (a.y - p.y) - (c.y - p.y) * (a.x - p.x)) / area;
  return {wa, wb, 1.0 - wa - wb};
}

/// The samples strictly inside the triangle: every barycentric weight above 1e-9.
int Inside(const Vec3& a, const Vec3& b, const Vec3& c, const std::vector<Vec3>& points) {
  int n = 0;
  for (const Vec3& p : points) {
    const std::array<double, 3> w = Weights(a, b, c, p);
    if (w[0] > 1e-9 && w[1] > 1e-9 && w[2] > 1e-9) ++n;
  }
  return n;
}

/// Whether every point is in the triangle (weights above -1e-12, in its plane).
bool AllIn(const Vec3& a, const Vec3& b, const Vec3& c, const std::vector<Vec3>& points) {
  for (const Vec3& p : points) {
    const std::array<double, 3> w = Weights(a, b, c, p);
    if (w[0] < -1e-12 || w[1] < -1e-12 || w[2] < -1e-12 || p.z != 0.0) return false;
  }
  return true;
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
  // 20 x 3 (a sliver: less than a quarter as high as long) at spacing 1: its height in three,
  // two rows inside, 1 apart, parallel to the longest edge; points about 1 apart on each.
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
  // 0.69.
  CHECK(SmallestGap(all) > 0.25);
  CHECK(LargestHole(a, b, c, all) < 0.8);
}

TEST_CASE("character samples: rows beside a sliver's sharp edges fill the gap to its rows") {
  // The 20 x 3 sliver with its edges sharp (a lone triangle's are boundaries), twice as many
  // samples along them and rows beside them (spacing 1, so h = 0.5 along the edges): beside
  // the longest edge the gap to its first row (height 1) takes one row at height 0.5, its ends
  // on the short edges (18 points: 16.67 long, 17 segments); beside each short edge (10.44
  // long, the apex 5.75 from it) the gap is at most the spacing, one row 0.5 from it (9.53
  // long, 10 segments: 11 points).
  const Vec3 a(0.0, 0.0, 0.0), b(20.0, 0.0, 0.0), c(10.0, 3.0, 0.0);
  PolygonMesh mesh;
  const std::vector<Vec3> with = LoneTriangleSamples(a, b, c, 1.0, &mesh, 2.0, true);
  const std::vector<Vec3> without = LoneTriangleSamples(a, b, c, 1.0, &mesh, 2.0, false);
  CHECK(AllIn(a, b, c, with));
  CHECK(with.size() == without.size() + 18 + 2 * 11);
  const auto at = [&](double y) {
    return std::count_if(with.begin(), with.end(),
                         [&](const Vec3& p) { return std::abs(p.y - y) < 1e-9; });
  };
  CHECK(at(0.5) == 18);
  // Between the longest edge and that row only the short edges' own samples and rows, near
  // the ends (within 0.5 / sin of the corner angle, 3.48, of a and b).
  for (const Vec3& p : with) {
    if (p.y > 1e-9 && p.y < 0.5 - 1e-9) CHECK((p.x < 3.5 || p.x > 16.5));
  }
  // The row beside the short edge a-c, 0.5 from it.
  const Vec3 n_ac = glm::normalize(Vec3(-(c.y - a.y), c.x - a.x, 0.0));
  const auto from_ac = std::count_if(with.begin(), with.end(), [&](const Vec3& p) {
    return std::abs(std::abs(glm::dot(p - a, n_ac)) - 0.5) < 1e-9;
  });
  CHECK(from_ac == 11);
}

TEST_CASE("character samples: a quarter as high as long is where the rows begin") {
  // Longest edge 10, spacing 1: 2.4 high is a sliver (its height in 3: rows of 6 and 3 points
  // inside), 2.6 is not (the grid of 10 segments: 36 points inside).
  PolygonMesh mesh;
  const Vec3 a(0.0, 0.0, 0.0), b(10.0, 0.0, 0.0);
  const Vec3 low(5.0, 2.4, 0.0), high(5.0, 2.6, 0.0);
  CHECK(Inside(a, b, low, LoneTriangleSamples(a, b, low, 1.0, &mesh)) == 6 + 3);
  CHECK(Inside(a, b, high, LoneTriangleSamples(a, b, high, 1.0, &mesh)) == 36);
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

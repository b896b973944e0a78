// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The samples a character part's fit adds on its triangles (sdk/src/offline/character/
// area_samples.h): about the spacing apart in every direction, slivers included.
#include "offline/character/area_samples.h"

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
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

namespace {

constexpr double kPi = 3.14159265358979323846;

/// A strip of `sides` long quads (each split into two slivers along a diagonal), 10 long along
/// z and `width` wide: wrapped round a prism of that many sides whose sides are `width` wide
/// (`bent`), or flat in the plane y = 0 (open at both sides). Vertices shared.
PolygonMesh SliverStrip(int sides, double width, bool bent) {
  PolygonMesh mesh;
  const double radius = 0.5 * width / std::sin(kPi / sides);
  const int columns = bent ? sides : sides + 1;
  for (int row = 0; row < 2; ++row) {
    for (int k = 0; k < columns; ++k) {
      const double a = 2.0 * kPi * k / sides;
      mesh.positions.push_back(bent ? Vec3(radius * std::cos(a), radius * std::sin(a), 10.0 * row)
                                    : Vec3(width * k, 0.0, 10.0 * row));
    }
  }
  mesh.face_offsets = {0};
  for (int k = 0; k < sides; ++k) {
    const Index a = static_cast<Index>(k), b = static_cast<Index>((k + 1) % columns);
    const Index c = b + static_cast<Index>(columns), d = a + static_cast<Index>(columns);
    mesh.AddFace({a, b, c});
    mesh.AddFace({a, c, d});
  }
  return mesh;
}

/// The samples on the segment from p to q (within 1e-9 of it, ends excluded), as fractions of
/// the way from p, sorted.
std::vector<double> OnSegment(const Vec3& p, const Vec3& q, const std::vector<Vec3>& points) {
  std::vector<double> out;
  const Vec3 d = q - p;
  for (const Vec3& x : points) {
    const double t = glm::dot(x - p, d) / glm::dot(d, d);
    if (t > 1e-9 && t < 1.0 - 1e-9 && glm::length(x - (p + t * d)) < 1e-9) out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST_CASE("character samples: along a curved sliver, points come as close as its turn asks") {
  // A prism of 16 sides 0.4 wide (the sides turn by 2 pi / 16 = 0.393 radians from one to the
  // next), 10 long in one row of quads: 32 slivers 0.4 high over their sides, spacing 2. With
  // a turn of 0.25 radians per sample, the spacing along them is 0.25 x 0.4 / 0.393 = 0.255:
  // 39 points on each 10-long side (ceil(10 / 0.255) = 40 segments) where the spacing alone
  // gives 4 (5 segments).
  const int sides = 16;
  const double width = 0.4, turn = 0.25;
  const PolygonMesh bent = SliverStrip(sides, width, true);
  ShadingSurface flat;
  flat.Build(bent, {}, 0.0, 0.0);
  const std::vector<Vec3> plain = character::AreaSamples(bent, flat, {}, 2.0, 0.5, 1.0, false);
  CHECK(character::AreaSamples(bent, flat, {}, 2.0, 0.5, 1.0, false, 0.0) == plain);
  const std::vector<Vec3> closer =
      character::AreaSamples(bent, flat, {}, 2.0, 0.5, 1.0, false, turn);
  const double step = turn * width / (2.0 * kPi / sides);
  const int segments = static_cast<int>(std::ceil(10.0 / step));
  for (int k = 0; k < sides; ++k) {
    const Vec3& p = bent.positions[static_cast<std::size_t>(k)];
    const Vec3& q = bent.positions[static_cast<std::size_t>(k + sides)];
    CHECK(OnSegment(p, q, plain).size() == 4);
    const std::vector<double> t = OnSegment(p, q, closer);
    CHECK(static_cast<int>(t.size()) == segments - 1);
    double gap = t.empty() ? 1.0 : std::max(t.front(), 1.0 - t.back());
    for (std::size_t i = 1; i < t.size(); ++i) gap = std::max(gap, t[i] - t[i - 1]);
    CHECK(10.0 * gap <= step + 1e-9);
  }
  // The diagonals (between two faces in one plane: no turn) take their faces' spacing too.
  const double diagonal_length = glm::length(bent.positions[sides + 1] - bent.positions[0]);
  const std::vector<double> diagonal =
      OnSegment(bent.positions[0], bent.positions[sides + 1], closer);
  CHECK(static_cast<int>(diagonal.size()) ==
        static_cast<int>(std::ceil(diagonal_length / step)) - 1);
  // Inside each sliver (0.4 x 10 / 10.008 high over its diagonal): its height in 2 at that
  // step, one row half way, half the diagonal long; on each end ring's edges (0.4, sharp: the
  // boundary) one point. Every point counted once.
  const double height = width * 10.0 / diagonal_length;
  REQUIRE(static_cast<int>(std::ceil(height / step)) == 2);
  const int row = static_cast<int>(std::ceil(0.5 * diagonal_length / step)) - 1;
  CHECK(static_cast<int>(closer.size()) == 2 * sides * row + sides * (segments - 1) +
                                               static_cast<int>(diagonal.size()) * sides +
                                               2 * sides);
  // One quad wound the other way (its normals flipped), its edges shaded smooth (so not
  // creases whatever its normals), turns the same: the same count.
  PolygonMesh flipped = bent;
  for (int f = 0; f < 2; ++f) {
    Index* v = &flipped.face_vertices[flipped.face_offsets[static_cast<Index>(f)]];
    std::swap(v[1], v[2]);
  }
  std::vector<std::array<std::uint32_t, 2>> smooth;
  for (int k = 0; k < sides; ++k) {
    const auto u = static_cast<std::uint32_t>(k);
    for (const auto w : {static_cast<std::uint32_t>(k + sides),
                         static_cast<std::uint32_t>((k + 1) % sides + sides)}) {
      smooth.push_back({std::min(u, w), std::max(u, w)});
    }
  }
  std::sort(smooth.begin(), smooth.end());
  ShadingSurface flat_flipped;
  flat_flipped.Build(flipped, {}, 0.0, 0.0);
  CHECK(character::AreaSamples(bent, flat, smooth, 2.0, 0.5, 1.0, false, turn).size() ==
        closer.size());
  CHECK(character::AreaSamples(flipped, flat_flipped, smooth, 2.0, 0.5, 1.0, false, turn).size() ==
        closer.size());
}

TEST_CASE("character samples: flat slivers, and curved ones across creases, keep the spacing") {
  // The same slivers in a plane do not turn; round the prism with a crease angle below their
  // turn (0.3 < 0.393 radians) every side is a crease, whose samples follow crease_samples.
  const PolygonMesh strip = SliverStrip(16, 0.4, false), bent = SliverStrip(16, 0.4, true);
  ShadingSurface flat_strip, flat_bent;
  flat_strip.Build(strip, {}, 0.0, 0.0);
  flat_bent.Build(bent, {}, 0.0, 0.0);
  CHECK(character::AreaSamples(strip, flat_strip, {}, 2.0, 0.5, 1.0, false, 0.25) ==
        character::AreaSamples(strip, flat_strip, {}, 2.0, 0.5, 1.0, false));
  CHECK(character::AreaSamples(bent, flat_bent, {}, 2.0, 0.3, 1.0, false, 0.25) ==
        character::AreaSamples(bent, flat_bent, {}, 2.0, 0.3, 1.0, false));
  // Below the crease angle the same prism's sides do turn (the test above).
  CHECK(character::AreaSamples(bent, flat_bent, {}, 2.0, 0.5, 1.0, false, 0.25).size() >
        character::AreaSamples(bent, flat_bent, {}, 2.0, 0.5, 1.0, false).size());
}

}  // namespace dermis

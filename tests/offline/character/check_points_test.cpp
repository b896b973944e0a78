// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The check points of a character part (sdk/src/offline/character/check_points.h): how many,
// where (on the triangles, spread evenly), reproducible, capped, and nothing from bad
// arguments.
#include "offline/character/check_points.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace dermis {
namespace {

/// A 10 x 4 rectangle in the plane z = 0 as two triangles, and a quad face (no triangle) beside
/// it.
PolygonMesh Rectangle() {
  PolygonMesh m;
  m.positions = {Vec3(0, 0, 0),  Vec3(10, 0, 0), Vec3(10, 4, 0), Vec3(0, 4, 0),
                 Vec3(20, 0, 0), Vec3(30, 0, 0), Vec3(30, 4, 0), Vec3(20, 4, 0)};
  m.face_offsets = {0};
  m.AddFace({0, 1, 2});
  m.AddFace({0, 2, 3});
  m.AddFace({4, 5, 6, 7});
  return m;
}

}  // namespace

TEST_CASE("check points: about the count asked for, on the triangles, spread evenly") {
  const PolygonMesh mesh = Rectangle();
  ShadingSurface flat;
  flat.Build(mesh, {}, 0.0, 0.0);
  // 2 per area 0.25^2: 40 / 0.0625 * 2 = 1280 points expected on the triangles' area 40.
  const std::vector<Vec3> p = character::CheckPoints(mesh, flat, 0.25, 2.0, 7, 1e6);
  CHECK(std::abs(static_cast<double>(p.size()) - 1280.0) <= 2.0);  // each face rounds once
  int left = 0, low = 0;
  for (const Vec3& q : p) {
    // On the rectangle, none on the quad face.
    CHECK(q.x >= 0.0);
    CHECK(q.x <= 10.0);
    CHECK(q.y >= 0.0);
    CHECK(q.y <= 4.0);
    CHECK(q.z == 0.0);
    left += q.x < 5.0;
    low += q.y < 2.0;
  }
  // Uniform over the area: each half holds about half (binomial sd 18 of 640).
  CHECK(std::abs(left - 640) < 90);
  CHECK(std::abs(low - 640) < 90);
  // The same points every time; another seed, other points, as many.
  CHECK(character::CheckPoints(mesh, flat, 0.25, 2.0, 7, 1e6) == p);
  const std::vector<Vec3> other = character::CheckPoints(mesh, flat, 0.25, 2.0, 8, 1e6);
  CHECK(other != p);
  CHECK(std::abs(static_cast<double>(other.size()) - 1280.0) <= 2.0);
  // A density that would give more than max_points gives about that many: 1e9 asked, 100.
  const std::size_t capped = character::CheckPoints(mesh, flat, 1e-4, 1.0, 7, 100.0).size();
  CHECK(capped >= 99u);
  CHECK(capped <= 101u);
  // A fraction of a point per face: the hash rounds it, on average right.
  std::size_t few = 0;
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    few += character::CheckPoints(mesh, flat, 10.0, 0.5, seed, 1e6).size();  // 0.1 per face
  }
  CHECK(few > 20);
  CHECK(few < 60);
}

TEST_CASE("check points: bad arguments give none") {
  const PolygonMesh mesh = Rectangle();
  ShadingSurface flat;
  flat.Build(mesh, {}, 0.0, 0.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  CHECK(character::CheckPoints(mesh, flat, 0.0, 1.0, 1, 1e6).empty());
  CHECK(character::CheckPoints(mesh, flat, -1.0, 1.0, 1, 1e6).empty());
  CHECK(character::CheckPoints(mesh, flat, nan, 1.0, 1, 1e6).empty());
  CHECK(character::CheckPoints(mesh, flat, inf, 1.0, 1, 1e6).empty());
  CHECK(character::CheckPoints(mesh, flat, 1.0, 0.0, 1, 1e6).empty());
  CHECK(character::CheckPoints(mesh, flat, 1.0, nan, 1, 1e6).empty());
  CHECK(character::CheckPoints(mesh, flat, 1.0, 1.0, 1, 0.0).empty());
  CHECK(character::CheckPoints(mesh, flat, 1.0, 1.0, 1, nan).empty());
  CHECK(character::CheckPoints(mesh, flat, 1.0, 1.0, 1, inf).empty());
  PolygonMesh empty;
  empty.face_offsets = {0};
  ShadingSurface none;
  none.Build(empty, {}, 0.0, 0.0);
  CHECK(character::CheckPoints(empty, none, 1.0, 1.0, 1, 1e6).empty());
}

}  // namespace dermis

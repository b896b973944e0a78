// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The data's boundary edges, and the boundary control vertices moved out so that the domain
// surface's boundary curve covers the data's boundary (docs/fitting.md, "Covering the data's
// boundary"), on a flat grid whose boundary curve is known exactly.
#include "dermis/offline/fit/boundary_cover.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "dermis/offline/build/domain_builder.h"
#include "dermis/offline/geometry/builtin_meshes.h"
#include "dermis/offline/geometry/polygon_mesh.h"
#include "dermis/surface/surface_evaluator.h"

using namespace dermis;

namespace {

// An n x n grid of unit quads in the plane z = 0 over [0, n]^2, counter-clockwise about +z
// (about -z when `flipped`).
PolygonMesh FlatGrid(int n, bool flipped = false) {
  PolygonMesh m;
  m.source_name = "flat grid";
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) m.positions.push_back(Vec3(i, j, 0.0));
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const Index a = j * (n + 1) + i;
      if (flipped) {
        m.AddFace({a, a + n + 1, a + n + 2, a + 1});
      } else {
        m.AddFace({a, a + 1, a + n + 2, a + n + 1});
      }
    }
  }
  return m;
}

// The square [lo, hi]^2 at z = 0 as counter-clockwise boundary edges, `per_side` on each side.
std::vector<std::pair<Vec3, Vec3>> Square(double lo, double hi, int per_side) {
  std::vector<Vec3> ring;
  const Vec3 corners[4] = {Vec3(lo, lo, 0.0), Vec3(hi, lo, 0.0), Vec3(hi, hi, 0.0),
                           Vec3(lo, hi, 0.0)};
  for (int s = 0; s < 4; ++s) {
    for (int k = 0; k < per_side; ++k) {
      const double t = static_cast<double>(k) / per_side;
      ring.push_back((1.0 - t) * corners[s] + t * corners[(s + 1) % 4]);
    }
  }
  std::vector<std::pair<Vec3, Vec3>> edges;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    edges.emplace_back(ring[i], ring[(i + 1) % ring.size()]);
  }
  return edges;
}

}  // namespace

TEST_CASE("boundary cover: BoundaryEdges finds the edges only one face has") {
  const PolygonMesh grid = FlatGrid(2);
  const std::vector<std::pair<Vec3, Vec3>> edges = BoundaryEdges(grid);
  REQUIRE(edges.size() == 8);
  double length = 0.0;
  for (const auto& e : edges) {
    length += glm::length(e.second - e.first);
    // Every boundary edge lies on the square's sides.
    const Vec3 m = 0.5 * (e.first + e.second);
    CHECK((m.x == 0.0 || m.x == 2.0 || m.y == 0.0 || m.y == 2.0));
  }
  CHECK(length == Approx(8.0));
  PolygonMesh cube;
  REQUIRE(MakeBuiltinMesh("cube", &cube).ok());
  CHECK(BoundaryEdges(cube).empty());
  // An edge two faces have the same way round is not a boundary edge; an index out of range
  // drops its edges.
  PolygonMesh twice = FlatGrid(1);
  twice.AddFace({0, 1, 3, 2});
  CHECK(BoundaryEdges(twice).empty());
  PolygonMesh bad = FlatGrid(1);
  bad.AddFace({0, 1, 7});
  CHECK(BoundaryEdges(bad).size() == 3);
}

TEST_CASE("boundary cover: the boundary curve moves out to the data's boundary") {
  // On a flat 4 x 4 grid the domain surface is the square [0, 4]^2 and its boundary curve the
  // square's sides (each patch reproduces the plane). Data whose boundary runs d beyond the
  // sides lies d beyond the curve; afterwards the curve runs along the data's boundary away
  // from the corners (whose vertices move diagonally), within rounding.
  const int n = 4;
  const double d = 0.125;
  ControlSurface surface;
  REQUIRE(BuildControlSurface(FlatGrid(n), DomainOptions(), &surface).ok());
  const ManifoldDomain& domain = *surface.domain;
  const std::vector<std::pair<Vec3, Vec3>> data = Square(-d, n + d, 32);

  std::vector<Vec3> one = surface.control.positions, two = one;
  BoundaryCoverOptions options;
  options.threads = 1;
  const BoundaryCoverReport r1 = CoverDataBoundary(domain, data, options, &one);
  options.threads = 2;
  const BoundaryCoverReport r2 = CoverDataBoundary(domain, data, options, &two);
  CHECK(r1.largest_excess == Approx(d).epsilon(1e-9));
  CHECK(r1.data_vertices_beyond == static_cast<std::int64_t>(data.size()));
  CHECK(r1.vertices_moved == 4 * n);  // every boundary vertex
  CHECK(r2.vertices_moved == r1.vertices_moved);
  CHECK(r2.largest_excess == r1.largest_excess);
  CHECK(one == two);
  // Each side's inner vertices moved straight out by d, the interior ones not at all.
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const Vec3& x = one[static_cast<std::size_t>(j * (n + 1) + i)];
      const bool corner = (i == 0 || i == n) && (j == 0 || j == n);
      if (corner) continue;
      const double ex = i == 0 ? -d : i == n ? d : 0.0;
      const double ey = j == 0 ? -d : j == n ? d : 0.0;
      CHECK(x.x == Approx(i + ex).margin(1e-12));
      CHECK(x.y == Approx(j + ey).margin(1e-12));
      CHECK(x.z == Approx(0.0).margin(1e-12));
    }
  }
  // The new curve along the side y = 0, away from the corners' faces: at y = -d within 5% of d
  // (the moved row is d wider than the rest, so the patches no longer reproduce the grid
  // exactly; 2.5% measured). Face i of the first row has that side as its edge 0, uv = (t, 0).
  std::vector<LocalPatch> patches(static_cast<std::size_t>(domain.num_vertices()));
  domain.FitPatches(one.data(), patches.data());
  for (Index f = 1; f + 1 < n; ++f) {
    for (int k = 0; k <= 8; ++k) {
      SurfacePoint sp;
      REQUIRE(EvaluateSurface(domain, patches.data(), nullptr, f, Vec2(k / 8.0, 0.0), &sp));
      CHECK(std::abs(sp.position.y + d) <= 0.05 * d);
      CHECK(sp.position.z == Approx(0.0).margin(1e-12));
    }
  }
  // Data inside the curve asks for nothing: nothing moves.
  std::vector<Vec3> inside = surface.control.positions;
  const BoundaryCoverReport r3 =
      CoverDataBoundary(domain, Square(0.25, n - 0.25, 32), BoundaryCoverOptions(), &inside);
  CHECK(r3.data_vertices_beyond == 0);
  CHECK(r3.vertices_moved == 0);
  CHECK(inside == surface.control.positions);
  // Data farther than a boundary edge's chord belongs to something else: ignored.
  std::vector<Vec3> far = surface.control.positions;
  const BoundaryCoverReport r4 =
      CoverDataBoundary(domain, Square(-1.5, n + 1.5, 32), BoundaryCoverOptions(), &far);
  CHECK(r4.vertices_moved == 0);
  CHECK(far == surface.control.positions);
  // A move is capped at half the mean length of the vertex's boundary edges.
  std::vector<Vec3> capped = surface.control.positions;
  const BoundaryCoverReport r5 =
      CoverDataBoundary(domain, Square(-0.9, n + 0.9, 32), BoundaryCoverOptions(), &capped);
  CHECK(r5.largest_excess == Approx(0.9).epsilon(1e-9));
  CHECK(capped[2].y == Approx(-0.5).margin(1e-12));  // vertex (2, 0)
  // A closed control mesh, no data boundary or mismatched sizes: nothing happens.
  std::vector<Vec3> wrong(3, Vec3(0.0));
  CHECK(CoverDataBoundary(domain, data, BoundaryCoverOptions(), &wrong).vertices_moved == 0);
  std::vector<Vec3> none = surface.control.positions;
  CHECK(CoverDataBoundary(domain, {}, BoundaryCoverOptions(), &none).vertices_moved == 0);
  PolygonMesh cube;
  REQUIRE(MakeBuiltinMesh("cube", &cube).ok());
  ControlSurface closed;
  REQUIRE(BuildControlSurface(cube, DomainOptions(), &closed).ok());
  std::vector<Vec3> cx = closed.control.positions;
  CHECK(CoverDataBoundary(*closed.domain, data, BoundaryCoverOptions(), &cx).vertices_moved == 0);
}

TEST_CASE("boundary cover: a data vertex beyond the curve moves the two ends of its edge") {
  // The data's boundary is the square's sides but for two points: (1.25, -d) beyond the side
  // y = 0, a quarter along the boundary edge from vertex (1, 0) to (2, 0), and (2.75, 4 + d)
  // beyond the side y = 4, a quarter along the edge from (3, 4) to (2, 4) (the boundary runs
  // right to left there). A point at t asks the edge's first end for min(1, 2 (1 - t)) of its
  // excess and the second for min(1, 2 t): (1, 0) and (3, 4) move out by d, (2, 0) and (2, 4)
  // by d / 2, nothing else moves. The same on the grid with the other orientation (normal -z).
  const int n = 4;
  const double d = 0.125;
  for (bool flipped : {false, true}) {
    INFO((flipped ? "normal -z" : "normal +z"));
    ControlSurface surface;
    REQUIRE(BuildControlSurface(FlatGrid(n, flipped), DomainOptions(), &surface).ok());
    std::vector<std::pair<Vec3, Vec3>> data = Square(0.0, n, 32);
    // Side y = 0 is ring[0 .. 31] (x = k / 8), side y = 4 is ring[64 .. 95] (x = 4 - k / 8).
    std::vector<Vec3> ring;
    for (const auto& e : data) ring.push_back(e.first);
    ring[10] = Vec3(1.25, -d, 0.0);
    ring[64 + 10] = Vec3(2.75, n + d, 0.0);
    if (flipped) std::reverse(ring.begin(), ring.end());
    data.clear();
    for (std::size_t i = 0; i < ring.size(); ++i) {
      data.emplace_back(ring[i], ring[(i + 1) % ring.size()]);
    }
    std::vector<Vec3> x = surface.control.positions;
    BoundaryCoverOptions options;
    options.tolerance = 1e-9;
    const BoundaryCoverReport r = CoverDataBoundary(*surface.domain, data, options, &x);
    CHECK(r.data_vertices_beyond == 2);
    CHECK(r.largest_excess == Approx(d).epsilon(1e-9));
    CHECK(r.vertices_moved == 4);
    auto at = [&](int i, int j) { return x[static_cast<std::size_t>(j * (n + 1) + i)]; };
    CHECK(at(1, 0).y == Approx(-d).margin(1e-8));
    CHECK(at(2, 0).y == Approx(-0.5 * d).margin(1e-8));
    CHECK(at(3, n).y == Approx(n + d).margin(1e-8));
    CHECK(at(2, n).y == Approx(n + 0.5 * d).margin(1e-8));
    std::size_t moved = 0;
    for (std::size_t v = 0; v < x.size(); ++v) {
      if (x[v] == surface.control.positions[v]) continue;
      ++moved;
      CHECK(x[v].x == surface.control.positions[v].x);  // straight out, across the side
      CHECK(x[v].z == Approx(0.0).margin(1e-12));
    }
    CHECK(moved == 4);
  }
}

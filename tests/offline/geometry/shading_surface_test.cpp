// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/offline/geometry/shading_surface.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <utility>

using namespace dermis;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// An open tube of `sides` flat sides round the unit circle, z from 0 to `rows`, each quad
/// split into two triangles; welded (one vertex per position). Shaded smooth: each corner's
/// normal is its vertex's radial direction; flat: each corner gets its side's normal.
struct Tube {
  PolygonMesh mesh;
  std::vector<Vec3> normals;  ///< 3 per face.
};

Tube MakeTube(int sides, int rows, bool smooth) {
  Tube t;
  auto index = [&](int k, int row) { return static_cast<Index>(row * sides + (k % sides)); };
  for (int row = 0; row <= rows; ++row) {
    for (int k = 0; k < sides; ++k) {
      const double a = 2.0 * kPi * k / sides;
      t.mesh.positions.push_back(Vec3(std::cos(a), std::sin(a), double(row)));
    }
  }
  auto radial = [&](Index v) {
    const Vec3& p = t.mesh.positions[static_cast<std::size_t>(v)];
    return Vec3(p.x, p.y, 0.0);
  };
  for (int row = 0; row < rows; ++row) {
    for (int k = 0; k < sides; ++k) {
      const Index q[4] = {index(k, row), index(k + 1, row), index(k + 1, row + 1),
                          index(k, row + 1)};
      const double mid = 2.0 * kPi * (k + 0.5) / sides;
      const Vec3 side(std::cos(mid), std::sin(mid), 0.0);
      for (const auto& tri : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}}) {
        t.mesh.AddFace({q[tri[0]], q[tri[1]], q[tri[2]]});
        for (int c : tri) t.normals.push_back(smooth ? radial(q[c]) : side);
      }
    }
  }
  return t;
}

/// The two faces of every interior edge, with the corners of its ends in each.
struct EdgeFaces {
  Index f[2];
  int a[2], b[2];  ///< Corner of the edge's first / second vertex in each face.
};

std::vector<EdgeFaces> InteriorEdges(const PolygonMesh& m) {
  std::map<std::pair<Index, Index>, std::vector<std::pair<Index, int>>> edges;
  for (Index f = 0; f < m.num_faces(); ++f) {
    const Index* v = &m.face_vertices[m.face_offsets[f]];
    for (int k = 0; k < 3; ++k) {
      const Index x = v[k], y = v[(k + 1) % 3];
      edges[{std::min(x, y), std::max(x, y)}].push_back({f, x < y ? k : (k + 1) % 3});
    }
  }
  std::vector<EdgeFaces> out;
  for (const auto& e : edges) {
    if (e.second.size() != 2) continue;
    EdgeFaces ef;
    for (int s = 0; s < 2; ++s) {
      ef.f[s] = e.second[static_cast<std::size_t>(s)].first;
      const Index* v = &m.face_vertices[m.face_offsets[ef.f[s]]];
      for (int k = 0; k < 3; ++k) {
        if (v[k] == e.first.first) ef.a[s] = k;
        if (v[k] == e.first.second) ef.b[s] = k;
      }
    }
    out.push_back(ef);
  }
  return out;
}

Vec3 OnEdge(const ShadingSurface& s, Index f, int a, int b, double t) {
  double w[3] = {0.0, 0.0, 0.0};
  w[a] = 1.0 - t;
  w[b] = t;
  return s.Point(f, w);
}

}  // namespace

TEST_CASE("shading surface: through the vertices, one curve along each edge", "[shading]") {
  for (bool smooth : {true, false}) {
    INFO((smooth ? "smooth" : "flat") << "-shaded octagonal tube");
    const Tube t = MakeTube(8, 3, smooth);
    ShadingSurface s;
    s.Build(t.mesh, t.normals, 0.5, 0.0);
    CHECK(s.curved() == smooth);
    for (Index f = 0; f < t.mesh.num_faces(); ++f) {
      const Index* v = &t.mesh.face_vertices[t.mesh.face_offsets[f]];
      for (int k = 0; k < 3; ++k) {
        double w[3] = {0.0, 0.0, 0.0};
        w[k] = 1.0;
        CHECK(glm::length(s.Point(f, w) - t.mesh.positions[static_cast<std::size_t>(v[k])]) <
              1e-14);
      }
    }
    // No cracks: both faces of every edge give the same points along it.
    for (const EdgeFaces& e : InteriorEdges(t.mesh)) {
      for (double u : {0.1, 0.37, 0.5, 0.9}) {
        CHECK(glm::length(OnEdge(s, e.f[0], e.a[0], e.b[0], u) -
                          OnEdge(s, e.f[1], e.a[1], e.b[1], u)) < 1e-12);
      }
    }
  }
}

TEST_CASE("shading surface: a smooth-shaded octagon rounds towards its circle", "[shading]") {
  // The midpoint of a side edge (between two neighbouring vertices of a ring) lies at
  // cos(pi/8) from the axis on the flat triangles; Phong's move there is shape * w_a w_b *
  // |(d.n_a) n_a - (d.n_b) n_b| with d the chord 2 sin(pi/8), each normal at pi/8 + pi/2 from
  // it: shape sin^2(pi/8) cos(pi/8) outwards, so the point lies at cos(pi/8)(1 + shape
  // sin^2(pi/8)). At shape 0.5: 0.9915, against 0.9239 flat.
  const Tube t = MakeTube(8, 2, true);
  for (double shape : {0.5, 0.75, 1.0}) {
    ShadingSurface s;
    s.Build(t.mesh, t.normals, shape, 0.0);
    const double c = std::cos(kPi / 8), sn = std::sin(kPi / 8);
    // Face 16's first edge: ring 1 (between the two rows of quads), vertices 8 and 9.
    double w[3] = {0.5, 0.5, 0.0};
    const Vec3 p = s.Point(16, w);
    CHECK(std::hypot(p.x, p.y) == Approx(c * (1.0 + shape * sn * sn)).epsilon(1e-12));
    CHECK(p.z == Approx(1.0).epsilon(1e-15));
    // The rings at the open ends are boundaries: straight.
    CHECK(std::hypot(s.Point(0, w).x, s.Point(0, w).y) == Approx(c).epsilon(1e-14));
    // The vertical edges (normals perpendicular to them) stay straight.
    double up[3] = {0.5, 0.0, 0.5};  // face 1's corners 0 and 2: vertex 0 and the one above
    const Vec3 q = s.Point(1, up);
    CHECK(std::hypot(q.x, q.y) == Approx(1.0).epsilon(1e-14));
  }
  // Every smooth-shaded edge of the tube is reported: 8 per ring, 8 vertical, 8 diagonal per
  // row of quads, less the rings at the open ends.
  ShadingSurface s;
  s.Build(t.mesh, t.normals, 0.5, 0.0);
  CHECK(s.smooth_edges().size() == 8u + 2u * 8u * 2u);
}

TEST_CASE("shading surface: hard edges, faces without normals and bad normals stay flat",
          "[shading]") {
  const Tube flat = MakeTube(8, 2, false);
  ShadingSurface s;
  s.Build(flat.mesh, flat.normals, 0.5, 0.0);
  // Only the edges inside a side are shaded smooth (the quads' diagonals and the middle ring's
  // pieces: both faces carry the side's normal), and their term is zero: the surface is the
  // flat triangles.
  CHECK(s.smooth_edges().size() == 24u);
  CHECK_FALSE(s.curved());
  for (Index f = 0; f < flat.mesh.num_faces(); ++f) {
    const Index* v = &flat.mesh.face_vertices[flat.mesh.face_offsets[f]];
    const double w[3] = {0.2, 0.3, 0.5};
    const Vec3 linear = 0.2 * flat.mesh.positions[static_cast<std::size_t>(v[0])] +
                        0.3 * flat.mesh.positions[static_cast<std::size_t>(v[1])] +
                        0.5 * flat.mesh.positions[static_cast<std::size_t>(v[2])];
    CHECK(glm::length(s.Point(f, w) - linear) < 1e-14);
  }
  // A smooth tube whose normals are missing (wrong count, zero or not finite) is flat too,
  // and shades no edge smooth where the normals are absent.
  const Tube smooth = MakeTube(8, 2, true);
  std::vector<Vec3> zero(smooth.normals.size(), Vec3(0.0));
  std::vector<Vec3> short_list(smooth.normals.begin(), smooth.normals.end() - 1);
  std::vector<Vec3> nan_first = smooth.normals;
  nan_first[0] = Vec3(std::nan(""), 0.0, 0.0);
  for (const std::vector<Vec3>* n : {&zero, &short_list}) {
    s.Build(smooth.mesh, *n, 0.5, 0.0);
    CHECK_FALSE(s.curved());
    CHECK(s.smooth_edges().empty());
  }
  s.Build(smooth.mesh, nan_first, 0.5, 0.0);
  const double mid[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
  const Index* v = &smooth.mesh.face_vertices[smooth.mesh.face_offsets[0]];
  Vec3 centre(0.0);
  for (int k = 0; k < 3; ++k) centre += smooth.mesh.positions[static_cast<std::size_t>(v[k])] / 3.0;
  CHECK(glm::length(s.Point(0, mid) - centre) < 1e-14);  // face 0 has no usable normals
  CHECK(std::isfinite(s.Point(1, mid).x));
  // Shape 0: the flat triangles, but the smooth edges are still found.
  s.Build(smooth.mesh, smooth.normals, 0.0, 0.0);
  CHECK_FALSE(s.curved());
  CHECK(s.smooth_edges().size() == 40u);
}

TEST_CASE("shading surface: max_move caps each edge's bulge, the same from both sides",
          "[shading]") {
  // A coarse smooth-shaded tube: each ring edge's midpoint moves 0.5 sin^2(pi/8) cos(pi/8) =
  // 0.0677 uncapped (above); with a cap of 0.02 it moves exactly 0.02, and no edge more.
  const Tube t = MakeTube(8, 2, true);
  ShadingSurface free_surface, capped;
  free_surface.Build(t.mesh, t.normals, 0.5, 0.0);
  capped.Build(t.mesh, t.normals, 0.5, 0.02);
  CHECK(free_surface.capped_edges() == 0);
  CHECK(capped.capped_edges() > 0);
  const double w[3] = {0.5, 0.5, 0.0};  // face 16: ring 1's edge from vertex 8 to 9
  const Vec3 flat = 0.5 * (t.mesh.positions[8] + t.mesh.positions[9]);
  CHECK(glm::length(free_surface.Point(16, w) - flat) ==
        Approx(0.5 * std::pow(std::sin(kPi / 8), 2) * std::cos(kPi / 8)).epsilon(1e-12));
  CHECK(glm::length(capped.Point(16, w) - flat) == Approx(0.02).epsilon(1e-12));
  for (const EdgeFaces& e : InteriorEdges(t.mesh)) {
    const Vec3 p0 = OnEdge(capped, e.f[0], e.a[0], e.b[0], 0.5);
    const Vec3 p1 = OnEdge(capped, e.f[1], e.a[1], e.b[1], 0.5);
    CHECK(glm::length(p0 - p1) < 1e-12);
    double lin[3] = {0.0, 0.0, 0.0};
    lin[e.a[0]] = lin[e.b[0]] = 0.5;
    const Index* v = &t.mesh.face_vertices[t.mesh.face_offsets[e.f[0]]];
    const Vec3 chord_mid = 0.5 * (t.mesh.positions[static_cast<std::size_t>(v[e.a[0]])] +
                                  t.mesh.positions[static_cast<std::size_t>(v[e.b[0]])]);
    CHECK(glm::length(p0 - chord_mid) <= 0.02 * (1.0 + 1e-12));
  }
}

namespace {

/// A bar of square cross-section (side 2) along x from 0 to 2 * `half`, bent by `bend`
/// radians about y at x = `half`: two segments of one quad per side, each quad split into two
/// triangles. Shaded as a box-modelled limb is: each side is smooth across the bend (its
/// vertices at the bend get the mean of the two faces' normals) and hard along the bar (the
/// long edges); the rings at the ends are open.
Tube MakeBentBar(double half, double bend) {
  Tube t;
  // Ring r (0, 1, 2) at the start, the bend and the end; corner c of the square (y, z).
  const double ys[4] = {-1.0, 1.0, 1.0, -1.0}, zs[4] = {-1.0, -1.0, 1.0, 1.0};
  auto point = [&](int r, int c) {
    if (r < 2) return Vec3(r * half, ys[c], zs[c]);
    // The second segment turns about y through the bend: its axis (cos, 0, -sin).
    const double ca = std::cos(bend), sa = std::sin(bend);
    const Vec3 base(half, ys[c], zs[c]);
    return base + half * Vec3(ca, 0.0, -sa) + zs[c] * Vec3(sa, 0.0, ca - 1.0);
  };
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) t.mesh.positions.push_back(point(r, c));
  }
  auto id = [](int r, int c) { return static_cast<Index>(4 * r + (c % 4)); };
  auto face_normal = [&](Index a, Index b, Index c) {
    const Vec3 &pa = t.mesh.positions[static_cast<std::size_t>(a)],
               &pb = t.mesh.positions[static_cast<std::size_t>(b)],
               &pc = t.mesh.positions[static_cast<std::size_t>(c)];
    return glm::normalize(glm::cross(pb - pa, pc - pa));
  };
  for (int side = 0; side < 4; ++side) {
    Vec3 n[2];
    Index q[2][4];
    for (int s = 0; s < 2; ++s) {
      q[s][0] = id(s, side);
      q[s][1] = id(s + 1, side);
      q[s][2] = id(s + 1, side + 1);
      q[s][3] = id(s, side + 1);
      n[s] = face_normal(q[s][0], q[s][1], q[s][2]);
    }
    const Vec3 mid = glm::normalize(n[0] + n[1]);
    for (int s = 0; s < 2; ++s) {
      for (const auto& tri : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}}) {
        t.mesh.AddFace({q[s][tri[0]], q[s][tri[1]], q[s][tri[2]]});
        // Corners 1 and 2 of the first segment's quad and 0 and 3 of the second's are at the
        // bend.
        for (int c : tri) {
          const bool at_bend = s == 0 ? (c == 1 || c == 2) : (c == 0 || c == 3);
          t.normals.push_back(at_bend ? mid : n[s]);
        }
      }
    }
  }
  return t;
}

double Deviation(const Tube& t, double shape) {
  ShadingSurface s;
  s.Build(t.mesh, t.normals, shape, 0.0);
  return s.NormalDeviation();
}

}  // namespace

TEST_CASE("shading surface: how far its normals are from the shading normals", "[shading]") {
  // The flat sides of a smooth-shaded octagonal tube: across a side the interpolated normal
  // turns linearly from one radial direction to the next, at atan(|1 - 2t| tan(pi/8)) from
  // the side's normal (t across the side; the normals are the same along the tube). Its mean
  // over t is atan(k) - ln(1 + k^2) / (2k), k = tan(pi/8): 0.20155 rad. 16 points per
  // triangle give it to about 1e-3 (the kink at the side's middle).
  const Tube round = MakeTube(8, 2, true);
  const double k = std::tan(kPi / 8);
  const double exact = std::atan(k) - std::log(1.0 + k * k) / (2.0 * k);
  CHECK(Deviation(round, 0.0) == Approx(exact).epsilon(5e-3));
  // Phong's surface follows them: half as far at shape 0.5.
  CHECK(Deviation(round, 0.5) < 0.55 * Deviation(round, 0.0));
  // Normals that point against the faces' winding give the same surface and the same measure.
  Tube inward = round;
  for (Vec3& n : inward.normals) n = -n;
  for (double shape : {0.0, 0.5}) {
    CHECK(Deviation(inward, shape) == Approx(Deviation(round, shape)).epsilon(1e-12));
  }
  // Shaded flat, the facets' normals are the shading normals at any shape (to acos's
  // precision near 1).
  CHECK(Deviation(MakeTube(8, 2, false), 0.5) < 1e-7);
  // A bar bent by 40 degrees, smooth across the bend only: along the two sides that turn, the
  // interpolated normal leans from 0 at the ends to 20 degrees at the bend, about 10 on
  // average, and the two sides the bend turns within do not lean: bend / 8 over the bar (its
  // outer side is a little longer). No surface with straight long edges through those corners
  // follows such normals better than the flat sides; Phong's parabolas along the quads'
  // diagonals only add to it.
  const double bend = 40.0 * kPi / 180.0;
  const Tube bar = MakeBentBar(3.0, bend);
  ShadingSurface s;
  s.Build(bar.mesh, bar.normals, 0.5, 0.0);
  REQUIRE(s.curved());
  const double flat = Deviation(bar, 0.0);
  CHECK(flat == Approx(bend / 8.0).epsilon(0.1));
  for (double shape : {0.25, 0.5, 0.75}) {
    INFO("shape " << shape);
    CHECK(Deviation(bar, shape) > flat);
  }
  // No normals at all: nothing to measure.
  Tube none = round;
  none.normals.clear();
  CHECK(Deviation(none, 0.5) == 0.0);
}

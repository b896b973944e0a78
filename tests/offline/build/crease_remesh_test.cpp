// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Feature-aware remeshing (docs/fitting.md, "Creases"): the crease chains of a reference
// surface, pairing that never uses a crease as a diagonal, quad remeshes of a capped
// cylinder and a box whose crease edges must come out as control edges on the crease, and the
// support rows beside closed crease loops (docs/characters.md, "Support rows beside crease
// loops").
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <vector>

#include "dermis/offline/build/control_mesh.h"
#include "dermis/offline/build/crease_chains.h"
#include "dermis/offline/build/crease_cut.h"
#include "dermis/offline/build/crease_support.h"
#include "dermis/offline/build/domain_builder.h"
#include "dermis/offline/build/quad_pairing.h"
#include "dermis/offline/build/quad_remesh.h"
#include "dermis/offline/build/reference_surface.h"
#include "dermis/surface/surface_evaluator.h"

using namespace dermis;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct TriMesh {
  std::vector<Vec3> x;
  std::vector<std::uint32_t> t;
  void Quad(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    t.insert(t.end(), {a, b, c, a, c, d});
  }
};

// A cylinder of radius 1 and height 2 around z, `around` segments and `rows` rows on the side,
// capped by fans: its rims (90 degree dihedral) are two closed creases of `around` edges.
TriMesh CappedCylinder(int around, int rows) {
  TriMesh m;
  for (int j = 0; j <= rows; ++j) {
    for (int i = 0; i < around; ++i) {
      const double a = 2.0 * kPi * i / around;
      m.x.push_back({std::cos(a), std::sin(a), 2.0 * j / rows});
    }
  }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * around + (i % around)); };
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < around; ++i) m.Quad(id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
  }
  const std::uint32_t bottom = static_cast<std::uint32_t>(m.x.size());
  m.x.push_back({0.0, 0.0, 0.0});
  m.x.push_back({0.0, 0.0, 2.0});
  for (int i = 0; i < around; ++i) {
    m.t.insert(m.t.end(), {bottom, id(i + 1, 0), id(i, 0)});
    m.t.insert(m.t.end(), {bottom + 1, id(i, rows), id(i + 1, rows)});
  }
  return m;
}

// The cube [0, 1]^3 with an n x n grid of quads (two triangles each) on every face, outward.
TriMesh GridCube(int n) {
  TriMesh m;
  std::vector<std::uint32_t> ids;
  auto vertex = [&](const Vec3& p) {
    for (std::size_t i = 0; i < m.x.size(); ++i) {
      if (glm::length(m.x[i] - p) < 1e-12) return static_cast<std::uint32_t>(i);
    }
    m.x.push_back(p);
    return static_cast<std::uint32_t>(m.x.size() - 1);
  };
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      auto at = [&](int i, int j) {
        Vec3 p(0.0);
        p[axis] = side;
        p[u] = static_cast<double>(i) / n;
        p[w] = static_cast<double>(j) / n;
        return vertex(p);
      };
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          // (u, w, axis) is right-handed: counter-clockwise in (u, w) faces +axis.
          if (side == 1) {
            m.Quad(at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
          } else {
            m.Quad(at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
          }
        }
      }
    }
  }
  return m;
}

// Edges of a polygon mesh, each once as (a, b), a < b.
std::vector<std::array<Index, 2>> Edges(const PolygonMesh& m) {
  std::vector<std::array<Index, 2>> e;
  for (Index f = 0; f < m.num_faces(); ++f) {
    const Index b = m.face_offsets[static_cast<std::size_t>(f)], s = m.face_size(f);
    for (Index k = 0; k < s; ++k) {
      const Index p = m.face_vertices[static_cast<std::size_t>(b + k)];
      const Index q = m.face_vertices[static_cast<std::size_t>(b + (k + 1) % s)];
      e.push_back({std::min(p, q), std::max(p, q)});
    }
  }
  std::sort(e.begin(), e.end());
  e.erase(std::unique(e.begin(), e.end()), e.end());
  return e;
}

// Distance from p to the closed polygon of `around` vertices on the unit circle at height z.
double PolygonDistance(const Vec3& p, int around, double z) {
  double best = 1e300;
  for (int i = 0; i < around; ++i) {
    const double a0 = 2.0 * kPi * i / around, a1 = 2.0 * kPi * (i + 1) / around;
    const Vec3 a(std::cos(a0), std::sin(a0), z), b(std::cos(a1), std::sin(a1), z);
    const double u = std::clamp(glm::dot(p - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
    best = std::min(best, glm::length(p - (a + u * (b - a))));
  }
  return best;
}

}  // namespace

TEST_CASE("creases: chains of a capped cylinder and of a box") {
  {
    const TriMesh m = CappedCylinder(32, 4);
    ReferenceSurface ref;
    REQUIRE(ref.Build(m.x, m.t, "cylinder").ok());
    CreaseChains c;
    c.Build(ref, 30.0, 50.0);
    // Side edges turn by 360/32 = 11.25 degrees, caps are flat: only the rims are creases.
    CHECK(c.edges().size() == 64);
    REQUIRE(c.num_chains() == 2);
    CHECK(c.num_closed() == 2);
    for (int k = 0; k < 2; ++k) {
      CHECK(c.chain(k).size() == 32);
      CHECK(c.length(k) == Approx(64.0 * std::sin(kPi / 32.0)));  // the 32-gon's perimeter
      // Half way between two rim points, the short way round, is on the polygon.
      const double z = c.chain(k)[0] < 32 ? 0.0 : 2.0;
      const Vec3 p = c.Between(k, Vec3(1.0, -0.1, z), Vec3(1.0, 0.1, z), 0.5);
      CHECK(p.x == Approx(1.0));
      CHECK(p.y == Approx(0.0).margin(1e-12));
      CHECK(PolygonDistance(p, 32, z) < 1e-12);
    }
    for (Index v = 0; v < 32; ++v) {
      CHECK(c.vertex_feature(v) >= 0);        // bottom rim
      CHECK(c.vertex_feature(128 + v) >= 0);  // top rim (4 rows up)
    }
    CHECK(c.vertex_feature(32 * 2) == kNoFeature);  // a side vertex
    CreaseChains none;
    none.Build(ref, 0.0, 50.0);
    CHECK(none.empty());
  }
  {
    const TriMesh m = GridCube(3);
    ReferenceSurface ref;
    REQUIRE(ref.Build(m.x, m.t, "cube").ok());
    CreaseChains c;
    c.Build(ref, 30.0, 50.0);
    CHECK(c.edges().size() == 12 * 3);  // the cube's 12 edges, 3 grid edges each
    CHECK(c.num_chains() == 12);        // from corner to corner
    CHECK(c.num_closed() == 0);
    int corners = 0;
    for (Index v = 0; v < static_cast<Index>(m.x.size()); ++v) {
      corners += c.vertex_feature(v) == kCornerFeature ? 1 : 0;
    }
    CHECK(corners == 8);
    for (int k = 0; k < 12; ++k) CHECK(c.length(k) == Approx(1.0));
  }
}

TEST_CASE("creases: pairing never makes a crease the diagonal of a quad") {
  // A 2 x 2 grid of unit squares, each split along its diagonal (a, c).
  std::vector<Vec3> x;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) x.push_back({double(i), double(j), 0.0});
  }
  std::vector<std::uint32_t> t;
  std::vector<std::array<std::uint32_t, 2>> diagonals;
  for (std::uint32_t j = 0; j < 2; ++j) {
    for (std::uint32_t i = 0; i < 2; ++i) {
      const std::uint32_t a = 3 * j + i, b = a + 1, c = a + 4, d = a + 3;
      t.insert(t.end(), {a, b, c, a, c, d});
      diagonals.push_back({a, c});
    }
  }
  std::sort(diagonals.begin(), diagonals.end());
  PolygonMesh free_pairs, kept;
  QuadPairingStats sf, sk;
  REQUIRE(PairTrianglesIntoQuads(x, t, QuadPairingOptions{}, &free_pairs, &sf).ok());
  CHECK(sf.quads == 4);  // the squares back
  REQUIRE(PairTrianglesIntoQuads(x, t, QuadPairingOptions{}, &kept, &sk, &diagonals).ok());
  const std::vector<std::array<Index, 2>> e = Edges(kept);
  for (const auto& d : diagonals) {
    CHECK(std::binary_search(e.begin(), e.end(), std::array<Index, 2>{Index(d[0]), Index(d[1])}));
  }
}

TEST_CASE("creases: a capped cylinder's rims and a box's edges are control edges") {
  struct Case {
    const char* name;
    TriMesh mesh;
    int target;
  };
  const Case cases[] = {{"capped cylinder", CappedCylinder(32, 4), 200},
                        {"cube", GridCube(6), 150}};
  for (const Case& cs : cases) {
    QuadRemeshOptions options;
    options.target_vertices = cs.target;
    options.crease_angle_deg = 30.0;
    PolygonMesh out;
    QuadRemeshReport r;
    const Status s = QuadRemesh(cs.mesh.x, cs.mesh.t, cs.name, options, &out, &r);
    INFO(cs.name << ": " << s.message());
    REQUIRE(s.ok());
    REQUIRE(ValidatePolygonMesh(out).ok());
    CHECK(r.crease_edges_kept == r.crease_edges);
    CHECK(r.control_crease_edges > 0);
    const bool cylinder = cs.name[0] == 'c' && cs.name[1] == 'a';
    // On-crease test, independent of the remesher's tags: a cylinder vertex on a rim plane at
    // radius > 0.9, or a cube vertex on two faces' planes.
    auto on_crease = [&](const Vec3& p) {
      if (cylinder) {
        const bool plane = std::abs(p.z) < 1e-9 || std::abs(p.z - 2.0) < 1e-9;
        return plane && std::hypot(p.x, p.y) > 0.9;
      }
      int planes = 0;
      for (int k = 0; k < 3; ++k) {
        planes += (std::abs(p[k]) < 1e-9 || std::abs(p[k] - 1.0) < 1e-9) ? 1 : 0;
      }
      return planes >= 2;
    };
    // Crease vertices lie on the crease polyline.
    int on = 0;
    for (const Vec3& p : out.positions) {
      if (!on_crease(p)) continue;
      ++on;
      if (cylinder) {
        CHECK(PolygonDistance(p, 32, p.z < 1.0 ? 0.0 : 2.0) < 1e-9);
      }
    }
    // The control edges along the creases cover them: their lengths add up to the rims'
    // polygons (or the cube's 12 edges), and there are as many as there are crease vertices
    // on closed rims (one more per chain on the cube's 12 open edges, corners shared).
    int crease_edges = 0;
    double length = 0.0;
    for (const auto& e : Edges(out)) {
      const Vec3& a = out.positions[static_cast<std::size_t>(e[0])];
      const Vec3& b = out.positions[static_cast<std::size_t>(e[1])];
      if (!on_crease(a) || !on_crease(b)) continue;
      if (cylinder && std::abs(a.z - b.z) > 1e-9) continue;
      if (!cylinder) {
        // Both ends on the same cube edge: they share two coordinates in {0, 1}.
        int shared = 0;
        for (int k = 0; k < 3; ++k) {
          shared += (std::abs(a[k] - b[k]) < 1e-9 &&
                     (std::abs(a[k]) < 1e-9 || std::abs(a[k] - 1.0) < 1e-9))
                        ? 1
                        : 0;
        }
        if (shared < 2) continue;
      }
      ++crease_edges;
      length += glm::length(a - b);
    }
    INFO(on << " crease vertices, " << crease_edges << " control edges on creases, length "
            << length << "; report: " << r.control_crease_edges << " of " << r.vertices);
    CHECK(crease_edges == r.control_crease_edges);
    if (cylinder) {
      CHECK(crease_edges == on);
      // Chords of the 32-gon: at most its perimeter, within 2 % of it.
      const double perimeter = 64.0 * std::sin(kPi / 32.0);
      CHECK(length <= 2.0 * perimeter + 1e-9);
      CHECK(length > 0.98 * 2.0 * perimeter);
      CHECK(crease_edges >= 2 * 12);  // enough edges that each rim stays round
    } else {
      CHECK(crease_edges == on + 4);  // 12 chains, 8 shared corners: E = V + 12 - 8
      CHECK(length == Approx(12.0));
      for (const Vec3& corner : {Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(1, 0, 0), Vec3(0, 1, 1)}) {
        bool found = false;
        for (const Vec3& p : out.positions) found |= glm::length(p - corner) < 1e-12;
        CHECK(found);
      }
    }
  }
}

TEST_CASE("creases: edges the input shades smooth are never creases") {
  // The capped cylinder's bottom rim named smooth (a source shading it soft): only the top rim
  // is a crease, for the chains and for the remesh, which renumbers nothing (the input is
  // welded already); either order of an edge's ends names it, and a pair that is no edge of
  // the input names nothing.
  const TriMesh m = CappedCylinder(32, 4);
  std::vector<std::array<std::uint32_t, 2>> smooth;
  for (std::uint32_t i = 0; i < 32; ++i) {
    const std::uint32_t a = i, b = (i + 1) % 32;
    smooth.push_back(i % 2 ? std::array<std::uint32_t, 2>{a, b}
                           : std::array<std::uint32_t, 2>{b, a});
  }
  smooth.push_back({0, 100});  // not an edge
  ReferenceSurface ref;
  REQUIRE(ref.Build(m.x, m.t, "cylinder").ok());
  CreaseChains c;
  c.Build(ref, 30.0, 50.0, smooth);
  CHECK(c.edges().size() == 32);
  REQUIRE(c.num_chains() == 1);
  for (Index v = 0; v < 32; ++v) {
    CHECK(c.vertex_feature(v) == kNoFeature);
    CHECK(c.vertex_feature(128 + v) >= 0);
  }
  QuadRemeshOptions options;
  options.target_vertices = 200;
  options.crease_angle_deg = 30.0;
  options.smooth_edges = smooth;
  PolygonMesh out;
  QuadRemeshReport r;
  const Status s = QuadRemesh(m.x, m.t, "cylinder", options, &out, &r);
  INFO(s.message());
  REQUIRE(s.ok());
  CHECK(r.crease_edges == 32);
  CHECK(r.crease_chains == 1);
  CHECK(r.crease_edges_kept == 32);
}

TEST_CASE("creases: BuildControlMesh renumbers the smooth edges through its weld") {
  // The capped cylinder with every triangle's corners its own vertices (as a glTF primitive
  // with split normals stores them): the bottom rim named smooth by one triangle's copies of
  // its ends, so the weld must carry the names over. Out-of-range indices and a pair the weld
  // collapses into one vertex name nothing.
  const TriMesh m = CappedCylinder(32, 4);
  PolygonMesh soup;
  std::vector<std::array<std::uint32_t, 2>> smooth;
  for (std::size_t t = 0; t < m.t.size(); t += 3) {
    const Index base = static_cast<Index>(soup.positions.size());
    for (int k = 0; k < 3; ++k) soup.positions.push_back(m.x[m.t[t + static_cast<std::size_t>(k)]]);
    soup.AddFace({base, base + 1, base + 2});
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = m.t[t + static_cast<std::size_t>(k)];
      const std::uint32_t b = m.t[t + static_cast<std::size_t>((k + 1) % 3)];
      if (a < 32 && b < 32) {  // a bottom rim edge, named by this triangle's copies
        smooth.push_back(
            {static_cast<std::uint32_t>(base + k), static_cast<std::uint32_t>(base + (k + 1) % 3)});
      }
    }
  }
  REQUIRE(smooth.size() == 64u);    // each rim edge from its side triangle and its cap triangle
  smooth.push_back({0, 1u << 30});  // out of range
  for (std::size_t j = 1; j < soup.positions.size(); ++j) {
    if (soup.positions[j] == soup.positions[0]) {  // a copy of vertex 0: welded into one
      smooth.push_back({0, static_cast<std::uint32_t>(j)});
      break;
    }
  }
  REQUIRE(smooth.size() == 66u);
  ControlMeshOptions options;
  options.method = ControlMeshMethod::kRemesh;
  options.target_vertices = 200;
  options.remesh.crease_angle_deg = 30.0;
  PolygonMesh control;
  ControlMeshInfo info;
  REQUIRE(BuildControlMesh(soup, options, &control, &info).ok());
  REQUIRE(info.method == "remesh");
  CHECK(info.quality.crease_edges == 64);  // both rims
  options.remesh.smooth_edges = smooth;
  REQUIRE(BuildControlMesh(soup, options, &control, &info).ok());
  REQUIRE(info.method == "remesh");
  CHECK(info.quality.crease_edges == 32);  // the top rim only
  CHECK(info.quality.crease_chains == 1);
}

namespace {

// The quad remesh of `m` keeping its creases at 30 degrees, and the reference's chains.
struct CreaseRemesh {
  ReferenceSurface ref;
  CreaseChains chains;
  PolygonMesh control;
};
void RemeshWithCreases(const TriMesh& m, int target, CreaseRemesh* out) {
  REQUIRE(out->ref.Build(m.x, m.t, "creased").ok());
  out->chains.Build(out->ref, 30.0, 50.0);
  QuadRemeshOptions options;
  options.target_vertices = target;
  options.crease_angle_deg = 30.0;
  QuadRemeshReport r;
  const Status s = QuadRemesh(m.x, m.t, "creased", options, &out->control, &r);
  INFO(s.message());
  REQUIRE(s.ok());
  REQUIRE(r.crease_edges_kept == r.crease_edges);
}

}  // namespace

TEST_CASE("creases: support rows move the vertices beside a closed loop towards it") {
  // The capped cylinder's two rims are closed loops. Every control vertex off the rims that
  // shares a control edge with rim vertices goes straight towards the rim point c closest to
  // it, keeping `keep` of its distance (identity projection: exactly); one whose rim
  // neighbours surround it, or whose c is further from its nearest rim neighbour than it is,
  // stays, and so does every other vertex.
  CreaseRemesh cr;
  RemeshWithCreases(CappedCylinder(32, 4), 300, &cr);
  const PolygonMesh before = cr.control;
  const std::size_t n = before.positions.size();
  auto rim_distance = [](const Vec3& p) {
    return std::min(PolygonDistance(p, 32, 0.0), PolygonDistance(p, 32, 2.0));
  };
  std::vector<char> on_rim(n, 0);
  for (std::size_t v = 0; v < n; ++v) on_rim[v] = rim_distance(before.positions[v]) < 1e-9;
  std::vector<std::vector<Vec3>> rim_neighbors(n);
  for (const auto& e : Edges(before)) {
    const std::size_t a = static_cast<std::size_t>(e[0]), b = static_cast<std::size_t>(e[1]);
    if (on_rim[a] && !on_rim[b]) rim_neighbors[b].push_back(before.positions[a]);
    if (on_rim[b] && !on_rim[a]) rim_neighbors[a].push_back(before.positions[b]);
  }
  // The expected targets, computed here from the rule, with the rim polygon's closest point.
  const double keep = 0.4;
  std::vector<char> moves(n, 0);
  std::vector<Vec3> target(n);
  int expected = 0, skipped = 0;
  for (std::size_t v = 0; v < n; ++v) {
    const std::vector<Vec3>& r = rim_neighbors[v];
    if (r.empty()) continue;
    const Vec3& x = before.positions[v];
    Vec3 mean(0.0), near(0.0);
    double d = 0.0, nearest = 1e300;
    for (const Vec3& y : r) {
      mean += y, d += glm::length(y - x);
      if (glm::length(y - x) < nearest) nearest = glm::length(y - x), near = y;
    }
    mean /= static_cast<double>(r.size());
    d /= static_cast<double>(r.size());
    const double z = r[0].z;  // the rim its neighbours lie on
    Vec3 c(0.0);
    double best = 1e300;
    for (int i = 0; i < 32; ++i) {
      const double a0 = 2.0 * kPi * i / 32, a1 = 2.0 * kPi * (i + 1) / 32;
      const Vec3 p(std::cos(a0), std::sin(a0), z), q(std::cos(a1), std::sin(a1), z);
      const double u = std::clamp(glm::dot(x - p, q - p) / glm::dot(q - p, q - p), 0.0, 1.0);
      const Vec3 w = p + u * (q - p);
      if (glm::length(x - w) < best) best = glm::length(x - w), c = w;
    }
    if (glm::length(mean - x) < 0.5 * d || glm::length(c - near) > nearest) {
      ++skipped;
      continue;
    }
    moves[v] = 1;
    target[v] = c + keep * (x - c);
    ++expected;
  }
  INFO(expected << " vertices to move, " << skipped << " left");
  REQUIRE(expected > 4 * 16);  // a row on the side and one on the cap, at both rims
  CreaseSupportResult res;
  auto identity = [](const Vec3& y) { return y; };
  REQUIRE(SupportCreaseLoops(cr.chains, keep, 1e-9, identity, &cr.control, &res).ok());
  CHECK(res.loops == 2);
  CHECK(res.moved == expected);
  CHECK(cr.control.face_vertices == before.face_vertices);
  for (std::size_t v = 0; v < n; ++v) {
    const Vec3 &x = before.positions[v], &y = cr.control.positions[v];
    if (!moves[v]) {
      CHECK(y == x);
      continue;
    }
    INFO("vertex " << v << " at " << x.x << " " << x.y << " " << x.z);
    CHECK(glm::length(y - target[v]) < 1e-9);
    CHECK(rim_distance(y) == Approx(keep * rim_distance(x)).epsilon(1e-9));
  }
  // A projection that puts every target back onto the cylinder: the same vertices move, onto
  // the cylinder, closer to their rim.
  CreaseRemesh onto;
  RemeshWithCreases(CappedCylinder(32, 4), 300, &onto);
  auto cylinder = [](const Vec3& y) {
    const double r = std::hypot(y.x, y.y);
    if (y.z > 1e-12 && y.z < 2.0 - 1e-12 && r > 0.0) return Vec3(y.x / r, y.y / r, y.z);
    return y;  // on a cap's plane already
  };
  REQUIRE(SupportCreaseLoops(onto.chains, keep, 1e-9, cylinder, &onto.control, &res).ok());
  CHECK(res.moved == expected);
  for (std::size_t v = 0; v < n; ++v) {
    if (!moves[v]) continue;
    const Vec3& y = onto.control.positions[v];
    CHECK(rim_distance(y) < rim_distance(before.positions[v]));
    const double r = std::hypot(y.x, y.y);
    CHECK((std::abs(r - 1.0) < 1e-12 || std::abs(y.z) < 1e-12 || std::abs(y.z - 2.0) < 1e-12));
  }
}

TEST_CASE("creases: no support rows beside open chains, and bad fractions are refused") {
  // A box's twelve edges are open chains between its corners: nothing moves.
  CreaseRemesh box;
  RemeshWithCreases(GridCube(6), 300, &box);
  const std::vector<Vec3> x = box.control.positions;
  auto identity = [](const Vec3& y) { return y; };
  CreaseSupportResult res;
  REQUIRE(SupportCreaseLoops(box.chains, 0.5, 1e-9, identity, &box.control, &res).ok());
  CHECK(res.loops == 0);
  CHECK(res.moved == 0);
  CHECK(box.control.positions == x);
  // keep 1 moves nothing; outside (0, 1], a negative or infinite tolerance: refused, untouched.
  CreaseRemesh cyl;
  RemeshWithCreases(CappedCylinder(32, 4), 300, &cyl);
  const std::vector<Vec3> y = cyl.control.positions;
  REQUIRE(SupportCreaseLoops(cyl.chains, 1.0, 1e-9, identity, &cyl.control, &res).ok());
  CHECK(res.moved == 0);
  for (double keep : {0.0, -0.5, 1.5, std::nan("")}) {
    const Status s = SupportCreaseLoops(cyl.chains, keep, 1e-9, identity, &cyl.control, &res);
    CHECK(s.code() == StatusCode::kInvalidInput);
    CHECK(s.message().find("crease support") != std::string::npos);
  }
  CHECK(!SupportCreaseLoops(cyl.chains, 0.5, -1.0, identity, &cyl.control, &res).ok());
  CHECK(!SupportCreaseLoops(cyl.chains, 0.5, HUGE_VAL, identity, &cyl.control, &res).ok());
  CHECK(cyl.control.positions == y);
  // A face naming a vertex out of range is refused before anything moves.
  PolygonMesh broken = cyl.control;
  broken.face_vertices[0] = static_cast<Index>(broken.positions.size());
  const Status s = SupportCreaseLoops(cyl.chains, 0.5, 1e-9, identity, &broken, &res);
  CHECK(s.code() == StatusCode::kInvalidInput);
  CHECK(broken.positions == y);
  // A rim vertex at NaN is on no chain and has no side to move to: no neighbour moves towards
  // it (every other position stays finite), and it stays NaN. A projection that gives NaN
  // leaves its vertex where it was.
  PolygonMesh nan_rim = cyl.control;
  std::size_t rim = 0;
  while (rim < y.size() && !(PolygonDistance(y[rim], 32, 0.0) < 1e-9)) ++rim;
  REQUIRE(rim < y.size());
  nan_rim.positions[rim] = Vec3(std::nan(""));
  REQUIRE(SupportCreaseLoops(cyl.chains, 0.5, 1e-9, identity, &nan_rim, &res).ok());
  CHECK(res.moved > 0);
  CHECK(std::isnan(nan_rim.positions[rim].x));
  for (std::size_t v = 0; v < y.size(); ++v) {
    if (v == rim) continue;
    const Vec3& p = nan_rim.positions[v];
    CHECK((std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)));
  }
  PolygonMesh nan_target = cyl.control;
  auto to_nan = [](const Vec3&) { return Vec3(std::nan("")); };
  REQUIRE(SupportCreaseLoops(cyl.chains, 0.5, 1e-9, to_nan, &nan_target, &res).ok());
  CHECK(res.moved == 0);
  CHECK(nan_target.positions == y);
}

namespace {

// The domain surface (no displacement) of `control` built with `seam`, and the largest
// distance between the two sides of every cut edge (boundary edges whose ends lie at the same
// two positions), sampled at 15 points inside each edge.
double SeamGap(const PolygonMesh& control, const std::vector<std::uint8_t>& seam,
               ControlSurface* cs, int* pairs) {
  REQUIRE(BuildControlSurface(control, DomainOptions{}, cs, &seam).ok());
  const ManifoldDomain& d = *cs->domain;
  const MeshTopology& topo = d.topology();
  const std::vector<Vec3>& x = cs->control.positions;
  using Key = std::array<double, 3>;
  auto key = [&](Index v) {
    const Vec3& p = x[static_cast<std::size_t>(v)];
    return Key{p.x, p.y, p.z};
  };
  std::map<std::pair<Key, Key>, std::vector<Index>> sides;  // half-edges by their ends
  for (Index h = 0; h < topo.num_halfedges(); ++h) {
    if (topo.twin(h) != kInvalidIndex) continue;
    Key a = key(topo.halfedge_origin(h)), b = key(topo.halfedge_dest(h));
    if (b < a) std::swap(a, b);
    sides[{a, b}].push_back(h);
  }
  double worst = 0.0;
  *pairs = 0;
  for (const auto& [ends, hs] : sides) {
    if (hs.size() != 2) continue;
    ++*pairs;
    for (int i = 1; i < 16; ++i) {
      Vec3 p[2];
      for (int s = 0; s < 2; ++s) {
        const Index h = hs[static_cast<std::size_t>(s)];
        const Index f = topo.halfedge_face(h);
        const int corner = static_cast<int>(h - topo.face_offset(f));
        const bool forward = key(topo.halfedge_origin(h)) == ends.first;
        const double t = forward ? i / 16.0 : 1.0 - i / 16.0;
        SurfacePoint sp;
        REQUIRE(EvaluateSurface(d, cs->patches.data(), nullptr, f,
                                CornerToFace(corner, Vec2(t, 0.0)), &sp));
        p[s] = sp.position;
      }
      worst = std::max(worst, glm::length(p[0] - p[1]));
    }
  }
  return worst;
}

}  // namespace

TEST_CASE("creases: a box cut open along its edges comes out a box, its seams closed") {
  // Each of the cube's 12 edges is a chain between corners, every control edge on them is
  // cut: six flat sides, each a surface of its own. With the seam operators the sides' domain
  // surfaces are exactly flat (every patch a plane: the rings are planar, the seam patches
  // interpolate the straight crease) and meet exactly along every cut edge.
  CreaseRemesh box;
  RemeshWithCreases(GridCube(6), 300, &box);
  PolygonMesh closed = box.control;
  CreaseCutResult cut;
  REQUIRE(CutAlongCreases(box.chains, 1e-9, &box.control, &cut).ok());
  REQUIRE(ValidatePolygonMesh(box.control).ok());
  MeshTopology topo;
  REQUIRE(MeshTopology::Build(box.control.num_vertices(), box.control.face_offsets,
                              box.control.face_vertices, &topo)
              .ok());
  CHECK(topo.num_components() == 6);
  CHECK(box.control.num_faces() == closed.num_faces());
  // Every control edge on the cube's edges was cut: each cube-edge vertex has two copies, each
  // corner three.
  int on_edges = 0, corners = 0;
  for (const Vec3& p : closed.positions) {
    int at_side = 0;  // coordinates at 0 or 1
    for (int a = 0; a < 3; ++a) at_side += std::abs(p[a]) < 1e-9 || std::abs(p[a] - 1.0) < 1e-9;
    on_edges += at_side == 2;
    corners += at_side == 3;
  }
  CHECK(corners == 8);
  CHECK(cut.new_vertices == on_edges + 2 * corners);
  CHECK(box.control.num_vertices() == closed.num_vertices() + cut.new_vertices);
  REQUIRE(cut.seam.size() == box.control.positions.size());
  int kinds[3] = {0, 0, 0};
  for (Index v = 0; v < box.control.num_vertices(); ++v) {
    const std::uint8_t s = cut.seam[static_cast<std::size_t>(v)];
    CHECK(s <= 2);
    CHECK((s != 0) == topo.is_boundary_vertex(v));
    ++kinds[s];
  }
  CHECK(kinds[2] == 3 * corners);   // the corners' copies: chain ends
  CHECK(kinds[1] == 2 * on_edges);  // inside the chains
  ControlSurface cs;
  int pairs = 0;
  CHECK(SeamGap(box.control, cut.seam, &cs, &pairs) < 1e-13);
  CHECK(pairs == cut.cut_edges);
  double off_side = 0.0;
  for (Index f = 0; f < cs.domain->num_faces(); ++f) {
    // The face's side: the coordinate its corners share.
    const Vec3 c = cs.control.positions[static_cast<std::size_t>(topo.face_vertex(f, 0))];
    const Vec3 e = cs.control.positions[static_cast<std::size_t>(topo.face_vertex(f, 2))];
    int axis = 0;
    for (int a = 0; a < 3; ++a) {
      if (std::abs(c[a] - e[a]) < 1e-12 && (std::abs(c[a]) < 1e-12 || std::abs(c[a] - 1) < 1e-12))
        axis = a;
    }
    for (int i = 0; i <= 4; ++i) {
      for (int j = 0; j <= 4; ++j) {
        SurfacePoint sp;
        REQUIRE(EvaluateSurface(*cs.domain, cs.patches.data(), nullptr, f, Vec2(i / 4.0, j / 4.0),
                                &sp));
        off_side = std::max(off_side, std::abs(sp.position[axis] - c[axis]));
      }
    }
  }
  CHECK(off_side < 1e-12);
  // Closed (no seam), the same control mesh rounds the edges: the surface leaves the sides.
  ControlSurface round;
  REQUIRE(BuildControlSurface(closed, DomainOptions{}, &round).ok());
  double bulge = 0.0;
  for (Index f = 0; f < round.domain->num_faces(); ++f) {
    SurfacePoint sp;
    REQUIRE(EvaluateSurface(*round.domain, round.patches.data(), nullptr, f, Vec2(0.5), &sp));
    for (int a = 0; a < 3; ++a)
      bulge = std::max(bulge, std::max(-sp.position[a], sp.position[a] - 1));
  }
  INFO("closed: the rounded box stands " << bulge << " outside the cube");
  CHECK(bulge > 1e-3);
  // Bad tolerances are refused and leave the mesh as it was.
  PolygonMesh again = closed;
  CHECK(CutAlongCreases(box.chains, -1.0, &again, &cut).code() == StatusCode::kInvalidInput);
  CHECK(CutAlongCreases(box.chains, HUGE_VAL, &again, &cut).code() == StatusCode::kInvalidInput);
  CHECK(again.face_vertices == closed.face_vertices);
}

TEST_CASE("creases: a crease that ends inside the surface is not cut, one across it is") {
  // A sheet folded along x = 0: 12 x 12 quads over [-1, 1] x [0, 2], z = 0.8 |x| s(y). With
  // s = 1 the fold (77 degrees) runs from boundary to boundary and the cut splits the sheet in
  // two; with s falling to 0 from y = 1 on it fades out inside, where a cut would end in a
  // slit whose two sides one chart cannot close, and nothing is cut.
  for (const bool through : {true, false}) {
    TriMesh m;
    const int n = 12;
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        const double x = -1.0 + 2.0 * i / n, y = 2.0 * j / n;
        const double s = through ? 1.0 : std::clamp(2.0 - y, 0.0, 1.0);
        m.x.push_back({x, y, 0.8 * std::abs(x) * s});
      }
    }
    auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) m.Quad(id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
    CreaseRemesh sheet;
    RemeshWithCreases(m, 150, &sheet);
    INFO((through ? "fold across" : "fold fading out")
         << ": " << sheet.chains.num_chains() << " chains");
    REQUIRE(sheet.chains.num_chains() >= 1);
    const PolygonMesh before = sheet.control;
    CreaseCutResult cut;
    REQUIRE(CutAlongCreases(sheet.chains, 1e-9, &sheet.control, &cut).ok());
    MeshTopology topo;
    REQUIRE(MeshTopology::Build(sheet.control.num_vertices(), sheet.control.face_offsets,
                                sheet.control.face_vertices, &topo)
                .ok());
    if (through) {
      CHECK(cut.cut_edges > 0);
      CHECK(topo.num_components() == 2);
      ControlSurface cs;
      int pairs = 0;
      CHECK(SeamGap(sheet.control, cut.seam, &cs, &pairs) < 1e-13);
      CHECK(pairs == cut.cut_edges);
    } else {
      CHECK(cut.cut_edges == 0);
      CHECK(cut.new_vertices == 0);
      CHECK(topo.num_components() == 1);
      CHECK(sheet.control.face_vertices == before.face_vertices);
      for (std::uint8_t s : cut.seam) CHECK(s == 0);
    }
  }
}

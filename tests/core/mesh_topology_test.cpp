// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/core/mesh_topology.h"

#include <catch2/catch.hpp>

#include "support/meshes.h"

using namespace dermis;

namespace {
MeshTopology BuildOk(const PolygonMesh& m) {
  MeshTopology t;
  const Status s = MeshTopology::Build(m.num_vertices(), m.face_offsets, m.face_vertices, &t);
  INFO(s.message());
  REQUIRE(s.ok());
  return t;
}
Status BuildStatus(Index nv, const std::vector<std::vector<Index>>& faces) {
  PolygonMesh m;
  m.positions.resize(nv);
  for (const auto& f : faces) m.AddFace(f);
  MeshTopology t;
  return MeshTopology::Build(nv, m.face_offsets, m.face_vertices, &t);
}

// Every ring is counter-clockwise: the previous corner of ring face i is the next corner of
// ring face i + 1, and the ring face's corner really is the vertex.
void CheckRings(const MeshTopology& t) {
  for (Index v = 0; v < t.num_vertices(); ++v) {
    const int k = t.valence(v);
    for (int i = 0; i < k; ++i) {
      const RingCorner rc = t.ring(v, i);
      const int n = t.face_size(rc.face);
      REQUIRE(t.face_vertex(rc.face, rc.corner) == v);
      REQUIRE(t.halfedge_ring_index(t.face_offset(rc.face) + rc.corner) == i);
      if (i + 1 < k || !t.is_boundary_vertex(v)) {
        const RingCorner nx = t.ring(v, (i + 1) % k);
        REQUIRE(t.face_vertex(rc.face, (rc.corner + n - 1) % n) ==
                t.face_vertex(nx.face, (nx.corner + 1) % t.face_size(nx.face)));
      }
    }
    if (t.is_boundary_vertex(v)) {
      const RingCorner first = t.ring(v, 0);
      REQUIRE(t.twin(t.face_offset(first.face) + first.corner) == kInvalidIndex);
      const RingCorner last = t.ring(v, k - 1);
      const Index h = t.face_offset(last.face) + last.corner;
      REQUIRE(t.twin(t.prev(h)) == kInvalidIndex);
    }
  }
}
}  // namespace

TEST_CASE("topology of a cube: valence 3 everywhere, closed, ordered rings", "[topology]") {
  const MeshTopology t = BuildOk(test::Builtin("cube"));
  CHECK(t.num_vertices() == 8);
  CHECK(t.num_faces() == 6);
  CHECK(t.num_edges() == 12);
  CHECK(t.is_all_quads());
  CHECK_FALSE(t.has_boundary());
  CHECK(t.num_components() == 1);
  for (Index v = 0; v < 8; ++v) {
    CHECK(t.valence(v) == 3);
    CHECK_FALSE(t.is_boundary_vertex(v));
  }
  for (Index h = 0; h < t.num_halfedges(); ++h) {
    REQUIRE(t.twin(h) != kInvalidIndex);
    CHECK(t.twin(t.twin(h)) == h);
    CHECK(t.halfedge_origin(t.twin(h)) == t.halfedge_dest(h));
  }
  CheckRings(t);
}

TEST_CASE("topology of open and mixed meshes: boundary rings start and end on the boundary",
          "[topology]") {
  for (const char* name : {"grid", "house", "octahedron", "prism7", "torus"}) {
    INFO(name);
    const MeshTopology t = BuildOk(test::Builtin(name));
    CheckRings(t);
  }
  const MeshTopology grid = BuildOk(test::Builtin("grid"));
  CHECK(grid.has_boundary());
  CHECK(grid.valence(0) == 1);
  CHECK(grid.is_boundary_vertex(0));
  CHECK(grid.valence(1) == 2);
  CHECK(grid.valence(6) == 4);
  CHECK_FALSE(grid.is_boundary_vertex(6));
  for (double sector : {0.5 * M_PI, M_PI, 1.5 * M_PI}) {
    const MeshTopology fan = BuildOk(test::FanMesh(5, sector));
    CHECK(fan.is_boundary_vertex(0));
    CHECK(fan.valence(0) == 5);
    CheckRings(fan);
  }
}

TEST_CASE("topology counts connected components", "[topology]") {
  PolygonMesh m = test::Builtin("cube");
  const PolygonMesh tet = test::Builtin("tetrahedron");
  const Index base = m.num_vertices();
  for (const Vec3& p : tet.positions) m.positions.push_back(p + Vec3(5, 0, 0));
  for (Index f = 0; f < tet.num_faces(); ++f) {
    std::vector<Index> face;
    for (Index h = tet.face_offsets[f]; h < tet.face_offsets[f + 1]; ++h) {
      face.push_back(base + tet.face_vertices[h]);
    }
    m.AddFace(face);
  }
  const MeshTopology t = BuildOk(m);
  CHECK(t.num_components() == 2);
  CHECK(t.face_component(0) == 0);
  CHECK(t.face_component(t.num_faces() - 1) == 1);
  CHECK_FALSE(t.is_all_quads());
}

TEST_CASE("topology rejects broken meshes with a message naming the element", "[topology]") {
  Status s = BuildStatus(4, {{0, 1, 5}});
  CHECK_FALSE(s.ok());
  CHECK_THAT(s.message(), Catch::Contains("face 0") && Catch::Contains("out of range"));
  s = BuildStatus(4, {{0, 1, 1, 2}});
  CHECK_THAT(s.message(), Catch::Contains("more than once"));
  s = BuildStatus(4, {{0, 1}});
  CHECK_THAT(s.message(), Catch::Contains("at least 3"));
  // Two triangles traversing the edge 0->1 the same way: inconsistent orientation.
  s = BuildStatus(4, {{0, 1, 2}, {0, 1, 3}});
  CHECK_THAT(s.message(), Catch::Contains("same direction"));
  // Three faces on one edge.
  s = BuildStatus(5, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  CHECK_FALSE(s.ok());
  // Bow tie: two triangles sharing only vertex 0.
  s = BuildStatus(5, {{0, 1, 2}, {0, 3, 4}});
  CHECK_THAT(s.message(), Catch::Contains("vertex 0") && Catch::Contains("non-manifold vertex"));
  // Named elements.
  ElementNamer namer;
  namer.face = [](Index f) { return "face " + std::to_string(f) + " (line 42)"; };
  MeshTopology t;
  s = MeshTopology::Build(3, {0, 3}, {0, 1, 7}, &t, &namer);
  CHECK_THAT(s.message(), Catch::Contains("line 42"));
}

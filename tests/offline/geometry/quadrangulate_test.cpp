// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/offline/geometry/quadrangulate.h"

#include <catch2/catch.hpp>

#include "dermis/core/mesh_topology.h"
#include "test_meshes.h"

using namespace dermis;

TEST_CASE("all-quad meshes are kept as they are", "[quadrangulate]") {
  const PolygonMesh cube = test::Builtin("cube");
  QuadMesh q;
  REQUIRE(Quadrangulate(cube, &q).ok());
  CHECK(q.positions == cube.positions);
  CHECK(q.quads == cube.face_vertices);
  CHECK(q.num_input_vertices == 8);
}

TEST_CASE("triangles, n-gons and mixed meshes are split once into quads", "[quadrangulate]") {
  for (const char* name : {"tetrahedron", "octahedron", "house", "prism5", "prism12"}) {
    INFO(name);
    const PolygonMesh m = test::Builtin(name);
    MeshTopology in;
    REQUIRE(MeshTopology::Build(m.num_vertices(), m.face_offsets, m.face_vertices, &in).ok());
    QuadMesh q;
    REQUIRE(Quadrangulate(m, &q).ok());
    // V' = V + F + E, F' = sum of face sizes.
    CHECK(q.positions.size() ==
          static_cast<size_t>(m.num_vertices() + m.num_faces() + in.num_edges()));
    CHECK(q.quads.size() == 4 * m.face_vertices.size());
    for (Index v = 0; v < m.num_vertices(); ++v) CHECK(q.positions[v] == m.positions[v]);
    MeshTopology out;
    REQUIRE(MeshTopology::BuildQuads(static_cast<Index>(q.positions.size()), q.quads, &out).ok());
    CHECK(out.is_all_quads());
    CHECK(out.has_boundary() == in.has_boundary());
    // Original vertices keep their valence; face points get valence = face size; edge points 4.
    for (Index v = 0; v < m.num_vertices(); ++v) CHECK(out.valence(v) == in.valence(v));
    for (Index f = 0; f < m.num_faces(); ++f) {
      CHECK(out.valence(m.num_vertices() + f) == m.face_size(f));
      Vec3 c(0.0);
      for (Index h = m.face_offsets[f]; h < m.face_offsets[f + 1]; ++h)
        c += m.positions[m.face_vertices[h]];
      CHECK(glm::length(q.positions[m.num_vertices() + f] - c / double(m.face_size(f))) < 1e-15);
    }
    for (Index e = 0; e < in.num_edges(); ++e) {
      CHECK(out.valence(m.num_vertices() + m.num_faces() + e) == 4);
    }
    for (Index f = 0; f < q.num_quads(); ++f) CHECK(q.quad_source_face[f] < m.num_faces());
  }
}

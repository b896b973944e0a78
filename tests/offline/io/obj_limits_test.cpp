// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The OBJ reader on inputs of the first fuzzing campaign (issue 19): index -2^63 (its negation
// overflowed), coordinates whose products overflow, and faces of many thousand vertices (the
// repeated-vertex check was quadratic); and the topology builder on the same faces.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "dermis/core/mesh_topology.h"
#include "dermis/offline/build/domain_builder.h"
#include "dermis/offline/geometry/polygon_mesh.h"
#include "dermis/offline/io/obj_io.h"

using namespace dermis;

namespace {

std::string ObjError(const std::string& text) {
  PolygonMesh m;
  const Status s = ParseObj(text, "t.obj", &m);
  CHECK_FALSE(s.ok());
  return s.message();
}

// One n-gon on the unit circle; `last` (1-based) appended as a repeated corner when > 0.
std::string RingObj(int n, int repeat) {
  std::string text;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * 3.141592653589793 * i / n;
    text += "v " + std::to_string(std::cos(a)) + " " + std::to_string(std::sin(a)) + " 0\n";
  }
  text += "f";
  for (int i = 1; i <= n; ++i) text += " " + std::to_string(i);
  if (repeat > 0) text += " " + std::to_string(repeat);
  return text + "\n";
}

}  // namespace

TEST_CASE("obj: extreme indices are refused with the line, never wrapped") {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  std::string e = ObjError(tri + "f 1 2 -9223372036854775808\n");
  INFO(e);
  CHECK(e.find("t.obj:4:") == 0);
  CHECK(e.find("before the first vertex") != std::string::npos);
  e = ObjError(tri + "f -9223372036854775807 1 2\n");
  CHECK(e.find("before the first vertex") != std::string::npos);
  e = ObjError(tri + "f 1 2 9223372036854775807\n");
  CHECK(e.find("too large") != std::string::npos);
  e = ObjError(tri + "f 1 2 -99999999999999999999999\n");
  CHECK(e.find("t.obj:4:") == 0);
  // The smallest relative index that exists still works.
  PolygonMesh m;
  REQUIRE(ParseObj(tri + "f -3 -2 -1\n", "t.obj", &m).ok());
  CHECK(m.face_vertices == std::vector<Index>{0, 1, 2});
}

TEST_CASE("obj: coordinates whose products overflow are refused before geometry") {
  // The reader keeps every finite number exactly; what computes with the mesh refuses
  // magnitudes whose products overflow (1e308 turned every normal into (0,0,1)).
  PolygonMesh m;
  REQUIRE(
      ParseObj("v -1e308 0 0\nv 1e308 0 0\nv 0 1e308 0\nv 0 0 1\nf 1 2 3 4\n", "t.obj", &m).ok());
  CHECK(m.positions[1].x == 1e308);
  Status s = CheckCoordinateRange(m);
  INFO(s.message());
  CHECK(s.message() ==
        "t.obj: vertex 0 (line 1) has a coordinate that is not finite or of magnitude above 1e12 "
        "(products of such coordinates overflow; rescale the model)");
  ControlSurface cs;
  s = BuildControlSurface(m, DomainOptions{}, &cs);
  CHECK(s.message().find("magnitude above 1e12") != std::string::npos);
  CHECK(cs.domain == nullptr);
  // 1e11 is fine.
  REQUIRE(ParseObj("v -1e11 0 0\nv 1e11 0 0\nv 0 1e11 0\nv 0 0 1\nf 1 2 3 4\n", "t.obj", &m).ok());
  CHECK(CheckCoordinateRange(m).ok());
}

TEST_CASE("obj: a face of 100,000 vertices is read, a repeated corner found") {
  const int n = 100000;
  PolygonMesh m;
  REQUIRE(ParseObj(RingObj(n, 0), "ring.obj", &m).ok());
  REQUIRE(m.num_faces() == 1);
  CHECK(m.face_vertices.size() == static_cast<size_t>(n));
  REQUIRE(ValidatePolygonMesh(m).ok());
  const std::string e = ObjError(RingObj(n, 77777));
  INFO(e);
  CHECK(e.find("uses vertex 77777 more than once") != std::string::npos);
  // The topology builder finds it too (a face list that did not come from the OBJ reader).
  std::vector<Index> offsets = {0, n + 1};
  std::vector<Index> verts(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) verts[static_cast<size_t>(i)] = i;
  verts.push_back(n / 2);
  MeshTopology topo;
  const Status s = MeshTopology::Build(n, offsets, verts, &topo);
  INFO(s.message());
  REQUIRE_FALSE(s.ok());
  CHECK(s.message().find("more than once") != std::string::npos);
  // Small faces: a corner repeated anywhere is still found.
  CHECK(ObjError("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4 2\n").find("uses vertex 2") !=
        std::string::npos);
}

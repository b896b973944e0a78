// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/offline/io/obj_io.h"

#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "test_meshes.h"

using namespace dermis;
namespace fs = std::filesystem;

namespace {
Status Parse(const std::string& text, PolygonMesh* m = nullptr) {
  PolygonMesh local;
  Status s = ParseObj(text, "in.obj", m ? m : &local);
  if (s.ok()) s = ValidatePolygonMesh(m ? *m : local);
  return s;
}
const char* kQuadHeader = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

fs::path TempDir() {
  const fs::path dir =
      fs::temp_directory_path() / ("dermis_obj_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}
}  // namespace

TEST_CASE("OBJ parser reads every face index form", "[obj]") {
  PolygonMesh m;
  const Status s = Parse(
      "# comment\nmtllib x.mtl\no thing\nv 0 0 0\nv 1 0 0 1.0\nv 1 1 0 0.5 0.5 0.5\nv 0 1 0\n"
      "vt 0 0\nvn 0 0 1\ns off\nusemtl m\n"
      "f 1/1/1 2//1 3/1 \\\n  4\n"
      "v 2 0 0\nf -4 -1 -3\n",
      &m);
  INFO(s.message());
  REQUIRE(s.ok());
  CHECK(m.num_vertices() == 5);
  CHECK(m.num_faces() == 2);
  CHECK(m.face_size(0) == 4);
  CHECK(m.face_vertices == std::vector<Index>{0, 1, 2, 3, 1, 4, 2});
  CHECK(m.face_lines == std::vector<int>{12, 15});
  CHECK(m.positions[1] == Vec3(1, 0, 0));
}

TEST_CASE("OBJ errors name the file, the line and the problem", "[obj]") {
  struct Bad {
    std::string text, expect;
  };
  const std::vector<Bad> cases = {
      {std::string(kQuadHeader) + "f 1 2 3 5\n", "in.obj:5: vertex index 5 is out of range"},
      {std::string(kQuadHeader) + "f 1 2 0\n", "in.obj:5: vertex index 0"},
      {std::string(kQuadHeader) + "f 1 2 -7\n", "in.obj:5: relative vertex index -7"},
      {std::string(kQuadHeader) + "f 1 2 2 3\n", "in.obj:5: the face uses vertex 2 more than once"},
      {std::string(kQuadHeader) + "f 1 2\n", "in.obj:5: a face needs at least 3 vertices"},
      {std::string(kQuadHeader) + "f 1 x 3\n", "in.obj:5: 'x' is not a vertex index"},
      {"v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "in.obj:1: vertex coordinate 'nan' is not finite"},
      {"v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n", "in.obj:2: vertex coordinate 'inf' is not finite"},
      {"v 0 0 0\nv 1e999 0 0\nv 0 1 0\nf 1 2 3\n",
       "in.obj:2: vertex coordinate '1e999' is not finite"},
      {"v 0 0\n", "in.obj:1: a vertex needs 3 coordinates"},
      {"v 0 0 abc\n", "in.obj:1: 'abc' is not a number"},
      {"", "in.obj: no vertices"},
      {"# nothing\n\n", "in.obj: no vertices"},
      {std::string(kQuadHeader), "in.obj: no faces"},
      // Non-manifold edge: three triangles on edge 1-2.
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n", "line 8"},
      // Inconsistent orientation.
      {std::string(kQuadHeader) + "v 2 0 0\nf 1 2 3\nf 1 2 5\n", "same direction"},
      // Non-manifold vertex (bow tie).
      {"v 0 0 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 -1 0\nf 1 2 3\nf 1 4 5\n", "non-manifold vertex"},
  };
  for (const Bad& b : cases) {
    INFO(b.text);
    const Status s = Parse(b.text);
    REQUIRE_FALSE(s.ok());
    CHECK(s.code() == StatusCode::kInvalidInput);
    CHECK_THAT(s.message(), Catch::Contains(b.expect));
    CHECK_THAT(s.message(), Catch::Contains("in.obj"));
  }
}

TEST_CASE("OBJ reading of missing, unreadable and binary files", "[obj]") {
  PolygonMesh m;
  Status s = ReadObj("/nonexistent/dir/mesh.obj", &m);
  CHECK(s.code() == StatusCode::kIoError);
  CHECK_THAT(s.message(), Catch::Contains("/nonexistent/dir/mesh.obj"));
  const fs::path dir = TempDir();
  s = ReadObj(dir.string(), &m);
  CHECK(s.code() == StatusCode::kIoError);
  CHECK_THAT(s.message(), Catch::Contains("directory"));
  const fs::path bin = dir / "binary.obj";
  {
    std::ofstream f(bin, std::ios::binary);
    f.write("v 0 0 0\0\1\2", 10);
  }
  s = ReadObj(bin.string(), &m);
  CHECK_FALSE(s.ok());
  CHECK_THAT(s.message(), Catch::Contains("binary.obj"));
  fs::remove_all(dir);
}

TEST_CASE("OBJ writing is exact and atomic", "[obj]") {
  const fs::path dir = TempDir();
  const std::vector<Vec3> pos = {{0.1, 1.0 / 3.0, -2e-17}, {1, 0, 0}, {0, 1, 1e300}};
  const std::vector<Vec3> nrm = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  const fs::path out = dir / "tri.obj";
  REQUIRE(WriteObj(out.string(), pos, nrm, {0, 1, 2}).ok());
  PolygonMesh m;
  REQUIRE(ReadObj(out.string(), &m).ok());
  REQUIRE(m.positions.size() == 3);
  for (int i = 0; i < 3; ++i) CHECK(m.positions[i] == pos[i]);  // bit-exact round trip
  // No temporary files are left behind.
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file() ? 1 : 0;
  CHECK(files == 1);
  // A write into a missing directory fails and leaves nothing.
  const Status s = WriteObj((dir / "missing" / "x.obj").string(), pos, nrm, {0, 1, 2});
  CHECK(s.code() == StatusCode::kIoError);
  CHECK_FALSE(fs::exists(dir / "missing"));
  fs::remove_all(dir);
}

TEST_CASE("polygon OBJ round trip keeps vertices and faces exactly", "[obj]") {
  const fs::path dir = TempDir();
  const PolygonMesh house = test::Builtin("house");
  REQUIRE(WritePolygonObj((dir / "house.obj").string(), house).ok());
  PolygonMesh back;
  REQUIRE(ReadObj((dir / "house.obj").string(), &back).ok());
  CHECK(back.positions == house.positions);
  CHECK(back.face_offsets == house.face_offsets);
  CHECK(back.face_vertices == house.face_vertices);
  fs::remove_all(dir);
}

TEST_CASE("unused vertices are compacted away", "[obj]") {
  PolygonMesh m;
  REQUIRE(Parse("v 9 9 9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 8 8 8\nf 2 3 4\n", &m).ok());
  std::vector<Index> map;
  CHECK(CompactUnusedVertices(&m, &map) == 2);
  CHECK(m.num_vertices() == 3);
  CHECK(m.face_vertices == std::vector<Index>{0, 1, 2});
  CHECK(map == std::vector<Index>{kInvalidIndex, 0, 1, 2, kInvalidIndex});
  CHECK(m.vertex_lines == std::vector<int>{2, 3, 4});
}

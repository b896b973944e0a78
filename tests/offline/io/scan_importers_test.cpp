// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// OBJ and PLY as scan importers (io::Register) and the fit input read through them.
#include "dermis/offline/io/scan_importers.h"

#include <catch2/catch.hpp>

#include "dermis/offline/io/obj_io.h"
#include "dermis/offline/io/ply_io.h"
#include "dermis/offline/io/point_input.h"
#include "support/temp_files.h"

using namespace dermis;

TEST_CASE("scan importers: OBJ and PLY by extension, scans only, same result as the readers") {
  ImporterRegistry r;
  io::Register(&r);
  REQUIRE(r.importers().size() == 2);
  CHECK(r.Find("a.OBJ", ImportKind::kScan)->name() == "obj");
  CHECK(r.Find("a.Ply", ImportKind::kScan)->name() == "ply");
  CHECK(r.Find("a.obj", ImportKind::kAsset) == nullptr);
  CHECK(r.Find("a.glb", ImportKind::kScan) == nullptr);

  test::TempDir dir("dermis_scan_importers");
  // A point cloud (OBJ without faces) and a PLY with a face and an unused vertex.
  test::WriteFile(dir.File("cloud.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0.5\n");
  test::WriteFile(dir.File("tri.ply"),
                  "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                  "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                  "end_header\n0 0 0\n1 0 0\n9 9 9\n0 1 0\n3 0 1 3\n");
  PolygonMesh via_registry, direct;
  REQUIRE(r.ImportScan(dir.File("cloud.obj"), &via_registry).ok());
  REQUIRE(ReadObj(dir.File("cloud.obj"), &direct, /*require_faces=*/false).ok());
  CHECK(via_registry.positions == direct.positions);
  CHECK(via_registry.vertex_lines == direct.vertex_lines);
  CHECK(via_registry.num_faces() == 0);
  REQUIRE(r.ImportScan(dir.File("tri.ply"), &via_registry).ok());
  REQUIRE(ReadPly(dir.File("tri.ply"), &direct).ok());
  CHECK(via_registry.positions == direct.positions);
  CHECK(via_registry.face_vertices == direct.face_vertices);

  // The fit input: the registry's importer, then unused vertices dropped.
  PolygonMesh fit;
  Index dropped = -1;
  REQUIRE(ReadFitInput(dir.File("tri.ply"), &fit, &dropped, &r).ok());
  CHECK(dropped == 1);
  CHECK(fit.num_vertices() == 3);
  REQUIRE(ReadFitInput(dir.File("cloud.obj"), &fit, &dropped).ok());  // default importers
  CHECK(dropped == 0);
  CHECK(fit.num_vertices() == 3);
  const Status s = ReadFitInput(dir.File("scan.xyz"), &fit, &dropped);
  CHECK(s.code() == StatusCode::kUnsupported);
  CHECK(s.message() == dir.File("scan.xyz") +
                           ": no importer reads '.xyz' files as scans (scans: obj .obj, ply .ply)");
}

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The plugins as importers beside OBJ and PLY, registered in the order the dermis tool uses:
// scans go to the OBJ/PLY importers, assets of the same files to Assimp, glTF to tinygltf
// with the embedded surface.
#include <catch2/catch.hpp>

#include "dermis/offline/io/scan_importers.h"
#include "dermis/plugins/plugins.h"
#include "support/temp_files.h"
#include "test_meshes.h"

using namespace dermis;

TEST_CASE("plugin importers: each file to its importer, by registration") {
  ImporterRegistry r;
  io::Register(&r);
  plugins::Register(&r);
  REQUIRE(r.importers().size() == 4);
  CHECK(r.Find("x.obj", ImportKind::kScan)->name() == "obj");
  CHECK(r.Find("x.obj", ImportKind::kAsset)->name() == "assimp");
  CHECK(r.Find("x.PLY", ImportKind::kAsset)->name() == "assimp");
  CHECK(r.Find("x.GLB", ImportKind::kAsset)->name() == "gltf");
  CHECK(r.Find("x.gltf", ImportKind::kAsset)->name() == "gltf");
  CHECK(r.Find("x.fbx", ImportKind::kAsset)->name() == "assimp");
  CHECK(r.Find("noext", ImportKind::kAsset)->name() == "assimp");  // Assimp looks inside
  CHECK(r.Find("x.glb", ImportKind::kScan) == nullptr);
  CHECK(r.Find("x.fbx", ImportKind::kScan) == nullptr);

  // A glTF that carries a Dermis surface: the registry hands it back with the asset.
  test::TempDir dir("dermis_plugin_importers");
  const Asset asset = test::TwoCylinders();
  GltfExportOptions options;
  options.dsurf_bytes = std::string("DSURF\r\n\x1a payload", 16);
  REQUIRE(ExportGltf(asset, options, dir.File("c.glb")).ok());
  ImportedAsset imported;
  REQUIRE(r.ImportAsset(dir.File("c.glb"), &imported).ok());
  CHECK(imported.embedded_dsurf == options.dsurf_bytes);
  CHECK(imported.asset.meshes.size() == asset.meshes.size());
  // A glTF without one, and an OBJ through Assimp: nothing embedded.
  REQUIRE(ExportGltf(asset, GltfExportOptions{}, dir.File("plain.gltf")).ok());
  REQUIRE(r.ImportAsset(dir.File("plain.gltf"), &imported).ok());
  CHECK(imported.embedded_dsurf.empty());
  test::WriteFile(dir.File("quad.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  imported.embedded_dsurf = "stale";
  REQUIRE(r.ImportAsset(dir.File("quad.obj"), &imported).ok());
  CHECK(imported.embedded_dsurf.empty());
  CHECK(imported.asset.meshes.size() == 1);
  PolygonMesh scan;
  REQUIRE(r.ImportScan(dir.File("quad.obj"), &scan).ok());
  CHECK(scan.num_faces() == 1);
  CHECK(scan.face_size(0) == 4);  // the scan importer keeps the quad; Assimp triangulates
}

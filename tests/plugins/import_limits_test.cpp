// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The importers' budgets and guards (issue 19; docs/reliability.md, "Limits"), each on a small
// generated file that shows what the first fuzzing campaign found: deep JSON (stack overflow in
// tinygltf), accessors without data decoded into gigabytes, a quadratic joint-index check, deep
// Collada nodes (stack overflow in Assimp), files of no known format (leaks inside Assimp).
#include <catch2/catch.hpp>
#include <string>

#include "dermis/core/limits.h"
#include "dermis/plugins/assimp.h"
#include "dermis/plugins/gltf.h"
#include "support/temp_files.h"

using namespace dermis;

namespace {

std::string GltfError(const test::TempDir& dir, const std::string& name, const std::string& text) {
  test::WriteFile(dir.File(name), text);
  Asset asset;
  const Status s = ImportGltf(dir.File(name), &asset);
  CHECK_FALSE(s.ok());
  CHECK(asset.meshes.empty());
  return s.message();
}

// One skinned triangle (joints 0 and 1) drawn by `nodes` nodes sharing mesh and skin; the
// third vertex names joint `last_joint`. Buffer data inline (base64 of the bytes below).
std::string InstancedSkin(int nodes, int last_joint) {
  // POSITION 3 x vec3 float, JOINTS_0 3 x u16vec4, WEIGHTS_0 3 x vec4 float.
  std::string bin;
  auto f32 = [&bin](float x) { bin.append(reinterpret_cast<const char*>(&x), 4); };
  auto u16 = [&bin](unsigned v) {
    bin.push_back(static_cast<char>(v & 0xff));
    bin.push_back(static_cast<char>(v >> 8));
  };
  for (float x : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) f32(x);
  for (unsigned j : {0u, 1u, 0u, 0u, 0u, 1u, 0u, 0u, static_cast<unsigned>(last_joint), 0u, 0u, 0u})
    u16(j);
  for (float w : {.5f, .5f, 0.f, 0.f, .5f, .5f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f}) f32(w);
  static const char* kB64 = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string b64;
  for (size_t i = 0; i < bin.size(); i += 3) {
    unsigned v = static_cast<unsigned char>(bin[i]) << 16;
    if (i + 1 < bin.size()) v |= static_cast<unsigned char>(bin[i + 1]) << 8;
    if (i + 2 < bin.size()) v |= static_cast<unsigned char>(bin[i + 2]);
    b64 += kB64[(v >> 18) & 63];
    b64 += kB64[(v >> 12) & 63];
    b64 += i + 1 < bin.size() ? kB64[(v >> 6) & 63] : '=';
    b64 += i + 2 < bin.size() ? kB64[v & 63] : '=';
  }
  std::string nodes_json = R"({"name":"j0","children":[1]},{"name":"j1","translation":[0,1,0]})";
  std::string scene = "0";
  for (int i = 0; i < nodes; ++i) {
    nodes_json += R"(,{"mesh":0,"skin":0})";
    scene += "," + std::to_string(i + 2);
  }
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[)" + scene +
         R"(]}],"nodes":[)" + nodes_json +
         R"(],"meshes":[{"primitives":[{"attributes":{"POSITION":0,"JOINTS_0":1,"WEIGHTS_0":2}}]}],)"
         R"("skins":[{"joints":[0,1]}],"accessors":[)"
         R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},)"
         R"({"bufferView":1,"componentType":5123,"count":3,"type":"VEC4"},)"
         R"({"bufferView":2,"componentType":5126,"count":3,"type":"VEC4"}],)"
         R"("bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":24},)"
         R"({"buffer":0,"byteOffset":60,"byteLength":48}],"buffers":[{"byteLength":108,"uri":)"
         R"("data:application/octet-stream;base64,)" +
         b64 + R"("}]})";
}

}  // namespace

TEST_CASE("gltf limits: JSON nested past the depth limit is refused before tinygltf") {
  test::TempDir dir;
  const int depth = 20000;
  const std::string deep = R"({"asset":{"version":"2.0"},"extras":)" + std::string(depth, '[') +
                           std::string(depth, ']') + "}";
  const std::string e = GltfError(dir, "deep.gltf", deep);
  INFO(e);
  CHECK(e == dir.File("deep.gltf") + ": JSON nested deeper than 64 levels (at byte 99): refused");
  // Brackets inside strings do not count; 64 levels are fine.
  const std::string ok = R"({"asset":{"version":"2.0","extras":{"s":"[[[[[[[[[[[[\"[[[[[[[[[[["},)"
                         R"("deep":)" +
                         std::string(60, '[') + std::string(60, ']') + "}}";
  test::WriteFile(dir.File("ok.gltf"), ok);
  Asset asset;
  const Status s = ImportGltf(dir.File("ok.gltf"), &asset);
  INFO(s.message());
  CHECK(s.ok());
}

TEST_CASE("gltf limits: accessors without data are held to the decoded-bytes budget") {
  test::TempDir dir;
  // 2^26 VEC3 from a 230-byte file: 1.5 GiB of decoded doubles (under the per-accessor cap).
  const std::string big =
      R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
      R"("nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"accessors":[{"componentType":5126,)"
      R"("count":67108864,"type":"VEC3","min":[0,0,0],"max":[0,0,0]}]})";
  std::string e = GltfError(dir, "big.gltf", big);
  INFO(e);
  CHECK(e.find("/accessors/0: decoding 201326592 more values would pass the import budget") !=
        std::string::npos);
  // One accessor of 2^21 VEC3 (48 MiB decoded) used by 40 primitives: each decode counts.
  std::string prims;
  for (int i = 0; i < 40; ++i)
    prims += std::string(i ? "," : "") + R"({"attributes":{"POSITION":0}})";
  const std::string shared = R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[)" + prims +
                             R"(]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],)"
                             R"("accessors":[{"componentType":5126,"count":2097152,"type":"VEC3",)"
                             R"("min":[0,0,0],"max":[0,0,0]}]})";
  e = GltfError(dir, "shared.gltf", shared);
  CHECK(e.find("import budget of " + std::to_string(limits::kImportBudgetBaseBytes +
                                                    limits::kImportBudgetBytesPerFileByte *
                                                        shared.size())) != std::string::npos);
  CHECK(e.find("decoded so far") != std::string::npos);
}

TEST_CASE("gltf limits: joint indices checked once per mesh, reported per node") {
  test::TempDir dir;
  // 3,000 nodes drawing one skinned mesh: imported (the check no longer scans the mesh per node).
  test::WriteFile(dir.File("many.gltf"), InstancedSkin(3000, 1));
  Asset asset;
  Status s = ImportGltf(dir.File("many.gltf"), &asset);
  INFO(s.message());
  REQUIRE(s.ok());
  CHECK(asset.nodes.size() == 3002);
  // A joint index past the skin's two joints is still reported with the first node using it.
  const std::string e = GltfError(dir, "bad.gltf", InstancedSkin(3, 2));
  CHECK(e.find("/meshes/0/primitives/0/attributes/JOINTS_0: vertex 2 has joint index 2 >= joint "
               "count 2 of skin 0 (used by node 2)") != std::string::npos);
}

TEST_CASE("gltf limits: a directory named .glb is named as a directory") {
  test::TempDir dir;
  std::filesystem::create_directory(dir.File("x.glb"));
  Asset asset;
  const Status s = ImportGltf(dir.File("x.glb"), &asset);
  CHECK(s.message() == dir.File("x.glb") + ": is a directory, not a glTF file");
}

TEST_CASE("assimp limits: deep XML, unknown formats and 3MF are refused before Assimp") {
  test::TempDir dir;
  std::string dae = R"(<?xml version="1.0"?><COLLADA version="1.4.1"><library_visual_scenes>)"
                    R"(<visual_scene id="s">)";
  for (int i = 0; i < 2000; ++i) dae += "<node id=\"n" + std::to_string(i) + "\">";
  for (int i = 0; i < 2000; ++i) dae += "</node>";
  dae += "</visual_scene></library_visual_scenes></COLLADA>\n";
  test::WriteFile(dir.File("deep.dae"), dae);
  Asset asset;
  Status s = ImportAssimp(dir.File("deep.dae"), &asset);
  CHECK(s.message() ==
        dir.File("deep.dae") + ": XML elements nested deeper than 256 levels: refused");
  test::WriteFile(dir.File("x.bin"), std::string(80, '\xae'));
  s = ImportAssimp(dir.File("x.bin"), &asset);
  CHECK(s.code() == StatusCode::kUnsupported);
  CHECK(s.message().find("no importer reads '.bin' files") != std::string::npos);
  test::WriteFile(dir.File("noext"), "solid x\nendsolid x\n");
  s = ImportAssimp(dir.File("noext"), &asset);
  CHECK(s.message().find("(no extension)") != std::string::npos);
  test::WriteFile(dir.File("x.3mf"), "PK\x03\x04");
  s = ImportAssimp(dir.File("x.3mf"), &asset);
  CHECK(s.message().find("3MF is not read") != std::string::npos);
  // Comments, CDATA and self-closing elements do not count as depth; 200 levels import.
  std::string fine = R"(<?xml version="1.0"?><!-- <a><a><a> --><COLLADA version="1.4.1">)"
                     R"(<asset><up_axis>Y_UP</up_axis></asset><library_visual_scenes>)"
                     R"(<visual_scene id="s">)";
  for (int i = 0; i < 200; ++i) fine += "<node id=\"n" + std::to_string(i) + "\"><extra/>";
  for (int i = 0; i < 200; ++i) fine += "</node>";
  fine +=
      "</visual_scene></library_visual_scenes><scene><instance_visual_scene url=\"#s\"/>"
      "</scene></COLLADA>\n";
  test::WriteFile(dir.File("fine.dae"), fine);
  s = ImportAssimp(dir.File("fine.dae"), &asset);
  CHECK(s.message().find("nested deeper") == std::string::npos);
}

namespace {

// A COLLADA file of one triangle: `accessor` holds the position accessor's count / stride /
// offset attributes, `p` the triangle list's indices.
std::string ColladaTriangle(const std::string& accessor, const std::string& p) {
  return std::string(R"(<?xml version="1.0"?><COLLADA version="1.4.1">)") +
         R"(<asset><up_axis>Y_UP</up_axis></asset><library_geometries><geometry id="g"><mesh>)"
         R"(<source id="p"><float_array id="pa" count="9">0 0 0 1 0 0 0 1 0</float_array>)"
         R"(<technique_common><accessor source="#pa" )" +
         accessor +
         R"(><param name="X" type="float"/><param name="Y" type="float"/>)"
         R"(<param name="Z" type="float"/></accessor></technique_common></source><vertices )"
         R"(id="v"><input semantic="POSITION" source="#p"/></vertices><triangles count="1">)"
         R"(<input semantic="VERTEX" source="#v" offset="0"/><p>)" +
         p +
         R"(</p></triangles></mesh></geometry></library_geometries><library_visual_scenes>)"
         R"(<visual_scene id="s"><node id="n"><instance_geometry url="#g"/></node>)"
         R"(</visual_scene></library_visual_scenes><scene><instance_visual_scene url="#s"/>)"
         R"(</scene></COLLADA>)";
}

}  // namespace

TEST_CASE("assimp limits: a COLLADA index list with a non-integer character is refused") {
  // fuzz_assimp found one stray byte in a <p> list making Assimp 5.2 allocate without bound.
  test::TempDir dir;
  test::WriteFile(dir.File("good.dae"), ColladaTriangle(R"(count="3" stride="3")", "0 1\n2"));
  Asset asset;
  Status s = ImportAssimp(dir.File("good.dae"), &asset);
  INFO(s.message());
  REQUIRE(s.ok());
  CHECK(asset.meshes.size() == 1);
  for (const char* bad : {"0 1x 2", "0 1 \xcf\xc9", "0 1.5 2"}) {
    test::WriteFile(dir.File("bad.dae"), ColladaTriangle(R"(count="3" stride="3")", bad));
    s = ImportAssimp(dir.File("bad.dae"), &asset);
    CHECK(s.message() == dir.File("bad.dae") +
                             ": COLLADA <p> holds a character that is not part of an integer: "
                             "refused");
  }
}

TEST_CASE("assimp limits: a COLLADA accessor reading past its array is refused") {
  // fuzz_assimp found stride="32" over a 360-value array read past the heap block in Assimp.
  test::TempDir dir;
  Asset asset;
  test::WriteFile(dir.File("good.dae"), ColladaTriangle(R"(count="3" stride="3")", "0 1 2"));
  Status s = ImportAssimp(dir.File("good.dae"), &asset);
  INFO(s.message());
  REQUIRE(s.ok());
  CHECK(asset.meshes.at(0).primitives.at(0).positions.size() == 3);
  test::WriteFile(dir.File("bad.dae"), ColladaTriangle(R"(count="3" stride="32")", "0 1 2"));
  s = ImportAssimp(dir.File("bad.dae"), &asset);
  CHECK(s.message() == dir.File("bad.dae") +
                           ": COLLADA <accessor source=\"#pa\" count=\"3\" stride=\"32\"> "
                           "reads past the 9 values of its array: refused");
  test::WriteFile(dir.File("offset.dae"),
                  ColladaTriangle(R"(count="3" stride="3" offset="1")", "0 1 2"));
  s = ImportAssimp(dir.File("offset.dae"), &asset);
  CHECK(s.message().find("reads past the 9 values of its array") != std::string::npos);
}

TEST_CASE("assimp limits: an OFF header declaring more than the file holds is refused") {
  // fuzz_assimp found an 828-byte OFF file declaring 10^35 faces: Assimp 5.2 reserved them.
  test::TempDir dir;
  const std::string quad = "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 3 2\n";
  test::WriteFile(dir.File("good.off"), quad);
  Asset asset;
  Status s = ImportAssimp(dir.File("good.off"), &asset);
  INFO(s.message());
  REQUIRE(s.ok());
  CHECK(asset.meshes.at(0).primitives.at(0).positions.size() == 4);
  test::WriteFile(dir.File("faces.off"), "OFF\n# comment\n4 99999999999 0\n0 0 0\n");
  s = ImportAssimp(dir.File("faces.off"), &asset);
  CHECK(s.message() == dir.File("faces.off") +
                           ": the OFF header declares 99999999999 faces, more than a file of 36 "
                           "bytes holds: refused");
  test::WriteFile(dir.File("vertices.off"), "OFF 1000 1 0\n0 0 0\n");
  s = ImportAssimp(dir.File("vertices.off"), &asset);
  CHECK(s.message().find("declares 1000 vertices, more than a file of 19 bytes") !=
        std::string::npos);
  // Without the keyword Assimp reads the counts all the same (found by fuzz_assimp: 40 GB).
  test::WriteFile(dir.File("nokeyword.off"), "11111111111 2 0\n0 0 0\n");
  s = ImportAssimp(dir.File("nokeyword.off"), &asset);
  CHECK(s.message().find("declares 11111111111 vertices, more than a file of 22 bytes") !=
        std::string::npos);
}

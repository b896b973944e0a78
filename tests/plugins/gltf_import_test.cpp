// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// ImportGltf(): small glTF files built here byte by byte (every decoded value is known), the
// bad inputs the importer must reject with a clear message, and the shared sample characters.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "dermis/plugins/gltf.h"

namespace dermis {
namespace {

using Json = nlohmann::json;
namespace fs = std::filesystem;

/// Little-endian byte buffer built from typed values (memcpy, like the file format).
class Bytes {
 public:
  template <typename T>
  std::size_t Put(std::initializer_list<T> values) {
    const std::size_t offset = data_.size();
    for (T v : values) {
      char raw[sizeof(T)];
      std::memcpy(raw, &v, sizeof(T));
      data_.append(raw, sizeof(T));
    }
    return offset;
  }
  std::size_t PutRaw(const std::string& raw) {
    const std::size_t offset = data_.size();
    data_ += raw;
    return offset;
  }
  void Align4() {
    while (data_.size() % 4 != 0) data_.push_back('\0');
  }
  std::size_t size() const { return data_.size(); }
  const std::string& str() const { return data_; }

 private:
  std::string data_;
};

std::string Base64(const std::string& in) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (unsigned(std::uint8_t(in[i])) << 16) |
                       (unsigned(std::uint8_t(in[i + 1])) << 8) | unsigned(std::uint8_t(in[i + 2]));
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i + 1 == in.size()) {
    const unsigned v = unsigned(std::uint8_t(in[i])) << 16;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == in.size()) {
    const unsigned v =
        (unsigned(std::uint8_t(in[i])) << 16) | (unsigned(std::uint8_t(in[i + 1])) << 8);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

std::string DataUri(const std::string& bytes) {
  return "data:application/octet-stream;base64," + Base64(bytes);
}

/// A fresh directory per test, removed at the end.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = fs::temp_directory_path() /
            ("dermis_gltf_import_" + std::to_string(rd()) + "_" + std::to_string(rd()));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string Write(const std::string& name, const std::string& bytes) const {
    const std::string file = (path_ / name).string();
    std::ofstream(file, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    return file;
  }

 private:
  fs::path path_;
};

void PutU32(std::string* s, std::uint32_t v) {
  char raw[4];
  std::memcpy(raw, &v, 4);
  s->append(raw, 4);
}

/// A GLB: 12-byte header, JSON chunk (space padded), BIN chunk (zero padded) if `bin` is set.
std::string MakeGlb(const std::string& json, const std::string& bin) {
  std::string j = json;
  while (j.size() % 4 != 0) j.push_back(' ');
  std::string b = bin;
  while (b.size() % 4 != 0) b.push_back('\0');
  std::string out = "glTF";
  PutU32(&out, 2);
  PutU32(&out, std::uint32_t(12 + 8 + j.size() + (b.empty() ? 0 : 8 + b.size())));
  PutU32(&out, std::uint32_t(j.size()));
  PutU32(&out, 0x4E4F534Au);
  out += j;
  if (!b.empty()) {
    PutU32(&out, std::uint32_t(b.size()));
    PutU32(&out, 0x004E4942u);
    out += b;
  }
  return out;
}

/// The document of a .gltf with one embedded buffer.
Json Document(const Bytes& bin) {
  Json doc;
  doc["asset"] = {{"version", "2.0"}, {"generator", "dermis test"}};
  doc["buffers"] = Json::array({{{"byteLength", bin.size()}, {"uri", DataUri(bin.str())}}});
  doc["scenes"] = Json::array({{{"nodes", {0}}}});
  doc["scene"] = 0;
  return doc;
}

Json View(std::size_t offset, std::size_t length, std::size_t stride = 0) {
  Json v = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}};
  if (stride != 0) v["byteStride"] = stride;
  return v;
}

Json Accessor(int view, int component_type, std::size_t count, const char* type,
              std::size_t offset = 0) {
  Json a = {{"componentType", component_type}, {"count", count}, {"type", type}};
  if (view >= 0) a["bufferView"] = view;
  if (offset != 0) a["byteOffset"] = offset;
  return a;
}

/// Imports, failing the test if it does not succeed.
Asset MustImport(const std::string& path, std::string* dsurf = nullptr) {
  Asset asset;
  const Status s = ImportGltf(path, &asset, dsurf);
  INFO(s.message());
  REQUIRE(s.ok());
  return asset;
}

/// Imports something broken: not ok, and the message names the file and `pointer`.
void ExpectError(const std::string& path, const std::string& pointer) {
  Asset asset;
  const Status s = ImportGltf(path, &asset);
  INFO("message: " << s.message());
  CHECK_FALSE(s.ok());
  CHECK(s.message().find(fs::path(path).filename().string()) != std::string::npos);
  CHECK(s.message().find(pointer) != std::string::npos);
}

constexpr int kByte = 5120, kUByte = 5121, kShort = 5122, kUShort = 5123, kUInt = 5125,
              kFloat = 5126;

/// A single-triangle document: POSITION (accessor 0) at bufferView 0, indices (accessor 1) at
/// bufferView 1, mesh 0 drawn by node 0.
Json Triangle(Bytes* bin) {
  const std::size_t p = bin->Put<float>({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const std::size_t i = bin->Put<std::uint16_t>({0, 1, 2});
  bin->Align4();
  Json doc = Document(*bin);
  doc["bufferViews"] = {View(p, 36), View(i, 6)};
  Json pos = Accessor(0, kFloat, 3, "VEC3");
  pos["min"] = {0, 0, 0};
  pos["max"] = {1, 1, 0};
  doc["accessors"] = {pos, Accessor(1, kUShort, 3, "SCALAR")};
  doc["meshes"] =
      Json::array({{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}});
  doc["nodes"] = Json::array({{{"mesh", 0}}});
  return doc;
}

TEST_CASE("gltf import: interleaved strided POSITION and NORMAL", "[gltf][import]") {
  TempDir dir;
  Bytes bin;
  bin.Put<std::uint32_t>({0xDEADBEEFu, 0xDEADBEEFu});  // 8 bytes before the view
  const float pos[3][3] = {{1.5f, -2.0f, 3.25f}, {4.0f, 5.5f, -6.0f}, {-7.0f, 8.0f, 9.125f}};
  const float nrm[3][3] = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}};
  for (int v = 0; v < 3; ++v) {
    bin.Put<float>({pos[v][0], pos[v][1], pos[v][2], nrm[v][0], nrm[v][1], nrm[v][2]});
    bin.Put<std::uint32_t>({0xFFFFFFFFu});  // padding inside the 28-byte stride
  }
  const std::size_t idx = bin.Put<std::uint16_t>({2, 0, 1});
  bin.Align4();
  Json doc = Document(bin);
  doc["bufferViews"] = {View(8, 84, 28), View(idx, 6)};
  doc["accessors"] = {Accessor(0, kFloat, 3, "VEC3"), Accessor(0, kFloat, 3, "VEC3", 12),
                      Accessor(1, kUShort, 3, "SCALAR")};
  doc["accessors"][0]["min"] = {-7, -2, -6};
  doc["accessors"][0]["max"] = {4, 8, 9.125};
  doc["meshes"] = Json::array(
      {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"indices", 2}}}}}});
  doc["nodes"] = Json::array({{{"mesh", 0}, {"name", "tri"}}});
  const Asset asset = MustImport(dir.Write("strided.gltf", doc.dump()));
  REQUIRE(asset.meshes.size() == 1);
  const AssetPrimitive& p = asset.meshes[0].primitives.at(0);
  REQUIRE(p.positions.size() == 3);
  REQUIRE(p.normals.size() == 3);
  for (int v = 0; v < 3; ++v) {
    CHECK(p.positions[v] == glm::vec3(pos[v][0], pos[v][1], pos[v][2]));
    CHECK(p.normals[v] == glm::vec3(nrm[v][0], nrm[v][1], nrm[v][2]));
  }
  CHECK(p.indices == std::vector<std::uint32_t>{2, 0, 1});
  CHECK(p.mode == PrimitiveMode::kTriangles);
  CHECK(asset.generator == "dermis test");
  CHECK(asset.nodes.at(0).name == "tri");
  CHECK(asset.default_scene == 0);
}

TEST_CASE("gltf import: normalized integer attributes", "[gltf][import]") {
  TempDir dir;
  Bytes bin;
  const std::size_t p = bin.Put<float>({0, 0, 0, 1, 0, 0, 0, 1, 0});
  // NORMAL as normalized i8 (KHR_mesh_quantization), -128 clamps to -1.
  const std::size_t n = bin.Put<std::int8_t>({127, 0, 0, -128, 0, 0, 0, -127, 0});
  bin.Align4();
  // TANGENT as normalized i16.
  const std::size_t t =
      bin.Put<std::int16_t>({32767, 0, 0, 32767, 0, -32768, 0, -32767, 0, 0, 32767, 32767});
  const std::size_t uv0 = bin.Put<std::uint8_t>({0, 255, 128, 51, 7, 200});
  bin.Align4();
  const std::size_t uv1 = bin.Put<std::uint16_t>({65535, 1000, 0, 32768, 12345, 65534});
  const std::size_t col = bin.Put<std::uint8_t>({255, 0, 10, 0, 255, 20, 0, 0, 30});
  bin.Align4();
  Json doc = Document(bin);
  doc["extensionsUsed"] = Json::array({"KHR_mesh_quantization"});
  doc["extensionsRequired"] = Json::array({"KHR_mesh_quantization"});
  doc["bufferViews"] = {View(p, 36),  View(n, 9),    View(t, 24),
                        View(uv0, 6), View(uv1, 12), View(col, 9)};
  doc["accessors"] = {Accessor(0, kFloat, 3, "VEC3"),  Accessor(1, kByte, 3, "VEC3"),
                      Accessor(2, kShort, 3, "VEC4"),  Accessor(3, kUByte, 3, "VEC2"),
                      Accessor(4, kUShort, 3, "VEC2"), Accessor(5, kUByte, 3, "VEC3")};
  for (int a = 1; a < 6; ++a) doc["accessors"][a]["normalized"] = true;
  doc["accessors"][0]["min"] = {0, 0, 0};
  doc["accessors"][0]["max"] = {1, 1, 0};
  doc["meshes"] = Json::array({{{"primitives",
                                 {{{"attributes",
                                    {{"POSITION", 0},
                                     {"NORMAL", 1},
                                     {"TANGENT", 2},
                                     {"TEXCOORD_0", 3},
                                     {"TEXCOORD_1", 4},
                                     {"COLOR_0", 5}}}}}}}});
  doc["nodes"] = Json::array({{{"mesh", 0}}});
  const Asset asset = MustImport(dir.Write("normalized.gltf", doc.dump()));
  const AssetPrimitive& prim = asset.meshes.at(0).primitives.at(0);
  // glTF 2.0 section 3.11: f = max(c / 127, -1), c / 255, max(c / 32767, -1), c / 65535.
  CHECK(prim.normals.at(0) == glm::vec3(1, 0, 0));
  CHECK(prim.normals.at(1) == glm::vec3(-1, 0, 0));  // -128 -> -1, not -128/127
  CHECK(prim.normals.at(2) == glm::vec3(0, -1, 0));
  CHECK(prim.tangents.at(0) == glm::vec4(1, 0, 0, 1));
  CHECK(prim.tangents.at(1) == glm::vec4(0, -1, 0, -1));
  CHECK(prim.tangents.at(2) == glm::vec4(0, 0, 1, 1));
  REQUIRE(prim.texcoords.size() == 2);
  CHECK(prim.texcoords[0][0] == glm::vec2(0.0f, 1.0f));
  CHECK(prim.texcoords[0][1] == glm::vec2(128.0f / 255.0f, 51.0f / 255.0f));
  CHECK(prim.texcoords[0][2] == glm::vec2(7.0f / 255.0f, 200.0f / 255.0f));
  CHECK(prim.texcoords[1][0] == glm::vec2(1.0f, 1000.0f / 65535.0f));
  CHECK(prim.texcoords[1][1] == glm::vec2(0.0f, 32768.0f / 65535.0f));
  CHECK(prim.texcoords[1][2] == glm::vec2(12345.0f / 65535.0f, 65534.0f / 65535.0f));
  REQUIRE(prim.colors.size() == 1);
  CHECK(prim.colors[0][0] == glm::vec4(1.0f, 0.0f, 10.0f / 255.0f, 1.0f));  // RGB: a = 1
  CHECK(prim.colors[0][2] == glm::vec4(0.0f, 0.0f, 30.0f / 255.0f, 1.0f));
}

TEST_CASE("gltf import: signed normalized values that are not extremes", "[gltf][import]") {
  TempDir dir;
  Bytes bin;
  const std::size_t p = bin.Put<float>({0, 0, 0, 1, 0, 0, 0, 1, 0});
  // Morph target POSITION deltas as normalized i8 and i16 (KHR_mesh_quantization).
  const std::size_t d8 = bin.Put<std::int8_t>({-128, -127, 64, 1, -1, 0, 100, -50, 3});
  bin.Align4();
  const std::size_t d16 =
      bin.Put<std::int16_t>({-32768, -32767, 16384, 1, -1, 0, 30000, -20000, 7});
  bin.Align4();
  Json doc = Document(bin);
  doc["extensionsUsed"] = Json::array({"KHR_mesh_quantization"});
  doc["bufferViews"] = {View(p, 36), View(d8, 9), View(d16, 18)};
  doc["accessors"] = {Accessor(0, kFloat, 3, "VEC3"), Accessor(1, kByte, 3, "VEC3"),
                      Accessor(2, kShort, 3, "VEC3")};
  doc["accessors"][1]["normalized"] = true;
  doc["accessors"][2]["normalized"] = true;
  doc["accessors"][0]["min"] = {0, 0, 0};
  doc["accessors"][0]["max"] = {1, 1, 0};
  doc["meshes"] = Json::array({{{"primitives",
                                 {{{"attributes", {{"POSITION", 0}}},
                                   {"targets", {{{"POSITION", 1}}, {{"POSITION", 2}}}}}}},
                                {"weights", {0.25, 0.5}}}});
  doc["nodes"] = Json::array({{{"mesh", 0}}});
  const Asset asset = MustImport(dir.Write("signed.gltf", doc.dump()));
  const AssetPrimitive& prim = asset.meshes.at(0).primitives.at(0);
  REQUIRE(prim.targets.size() == 2);
  const std::int8_t c8[9] = {-128, -127, 64, 1, -1, 0, 100, -50, 3};
  const std::int16_t c16[9] = {-32768, -32767, 16384, 1, -1, 0, 30000, -20000, 7};
  for (int v = 0; v < 3; ++v) {
    for (int c = 0; c < 3; ++c) {
      CHECK(prim.targets[0].positions.at(v)[c] == std::max(float(c8[v * 3 + c]) / 127.0f, -1.0f));
      CHECK(prim.targets[1].positions.at(v)[c] ==
            std::max(float(c16[v * 3 + c]) / 32767.0f, -1.0f));
    }
  }
  CHECK(asset.meshes[0].weights == std::vector<float>{0.25f, 0.5f});
}

TEST_CASE("gltf import: sparse accessors with and without a base bufferView", "[gltf][import]") {
  TempDir dir;
  Bytes bin;
  const std::size_t base = bin.Put<float>({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
  const std::size_t sidx = bin.Put<std::uint8_t>({1, 3});
  bin.Align4();
  const std::size_t sval = bin.Put<float>({5, 6, 7, -1, -2, -3});
  const std::size_t tidx = bin.Put<std::uint16_t>({2});
  bin.Align4();
  const std::size_t tval = bin.Put<float>({0.5f, 0.25f, 0.125f});
  Json doc = Document(bin);
  doc["bufferViews"] = {View(base, 48), View(sidx, 2), View(sval, 24), View(tidx, 2),
                        View(tval, 12)};
  Json positions = Accessor(0, kFloat, 4, "VEC3");
  positions["sparse"] = {{"count", 2},
                         {"indices", {{"bufferView", 1}, {"componentType", kUByte}}},
                         {"values", {{"bufferView", 2}}}};
  positions["min"] = {-1, -2, -3};
  positions["max"] = {5, 6, 7};
  Json deltas = Accessor(-1, kFloat, 4, "VEC3");  // no bufferView: zeros plus sparse values
  deltas["sparse"] = {{"count", 1},
                      {"indices", {{"bufferView", 3}, {"componentType", kUShort}}},
                      {"values", {{"bufferView", 4}}}};
  doc["accessors"] = {positions, deltas};
  doc["meshes"] = Json::array(
      {{{"primitives",
         {{{"attributes", {{"POSITION", 0}}}, {"mode", 0}, {"targets", {{{"POSITION", 1}}}}}}}}});
  doc["nodes"] = Json::array({{{"mesh", 0}}});
  const Asset asset = MustImport(dir.Write("sparse.gltf", doc.dump()));
  const AssetPrimitive& prim = asset.meshes.at(0).primitives.at(0);
  CHECK(prim.mode == PrimitiveMode::kPoints);
  CHECK(prim.positions == std::vector<glm::vec3>{{0, 0, 0}, {5, 6, 7}, {1, 1, 0}, {-1, -2, -3}});
  REQUIRE(prim.targets.size() == 1);
  CHECK(prim.targets[0].positions ==
        std::vector<glm::vec3>{{0, 0, 0}, {0, 0, 0}, {0.5f, 0.25f, 0.125f}, {0, 0, 0}});
}

TEST_CASE("gltf import: KHR_mesh_quantization u16 positions keep the node scale",
          "[gltf][import]") {
  TempDir dir;
  Bytes bin;
  const std::size_t p = bin.Put<std::uint16_t>({0, 0, 0, 65535, 100, 7, 200, 65535, 3});
  bin.Align4();
  Json doc = Document(bin);
  doc["extensionsUsed"] = Json::array({"KHR_mesh_quantization"});
  doc["extensionsRequired"] = Json::array({"KHR_mesh_quantization"});
  doc["bufferViews"] = Json::array({View(p, 18)});
  doc["accessors"] = Json::array({Accessor(0, kUShort, 3, "VEC3")});
  doc["accessors"][0]["min"] = {0, 0, 0};
  doc["accessors"][0]["max"] = {65535, 65535, 7};
  doc["meshes"] = Json::array({{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}});
  doc["nodes"] = Json::array({{{"mesh", 0},
                               {"scale", {0.5, 0.25, 2.0}},
                               {"translation", {1, 2, 3}},
                               {"rotation", {0, 0.6, 0, 0.8}}}});
  const Asset asset = MustImport(dir.Write("quantized.gltf", doc.dump()));
  const AssetPrimitive& prim = asset.meshes.at(0).primitives.at(0);
  CHECK(prim.positions ==
        std::vector<glm::vec3>{{0, 0, 0}, {65535, 100, 7}, {200, 65535, 3}});  // not normalized
  const AssetNode& node = asset.nodes.at(0);
  CHECK_FALSE(node.has_matrix);
  CHECK(node.scale == glm::dvec3(0.5, 0.25, 2.0));
  CHECK(node.translation == glm::dvec3(1, 2, 3));
  CHECK(node.rotation.w == 0.8);
  CHECK(node.rotation.y == 0.6);
  CHECK(node.rotation.x == 0.0);
}

/// Two JOINTS/WEIGHTS sets on 3 vertices, a skin of 2 joints without inverseBindMatrices and
/// the mesh drawn by nodes 0 and 3. `joint` is JOINTS_1 of vertex 0.
Json TwoSetSkin(Bytes* bin, std::uint16_t joint) {
  const std::size_t p = bin->Put<float>({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const std::size_t j0 = bin->Put<std::uint8_t>({0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0});
  const std::size_t j1 = bin->Put<std::uint16_t>({joint, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
  const std::size_t w0 = bin->Put<float>({0.5f, 0.25f, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0});
  const std::size_t w1 = bin->Put<std::uint8_t>({255, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
  Json doc = Document(*bin);
  doc["bufferViews"] = {View(p, 36), View(j0, 12), View(j1, 24), View(w0, 48), View(w1, 12)};
  doc["accessors"] = {Accessor(0, kFloat, 3, "VEC3"), Accessor(1, kUByte, 3, "VEC4"),
                      Accessor(2, kUShort, 3, "VEC4"), Accessor(3, kFloat, 3, "VEC4"),
                      Accessor(4, kUByte, 3, "VEC4")};
  doc["accessors"][4]["normalized"] = true;
  doc["accessors"][0]["min"] = {0, 0, 0};
  doc["accessors"][0]["max"] = {1, 1, 0};
  doc["meshes"] = Json::array({{{"primitives",
                                 {{{"attributes",
                                    {{"POSITION", 0},
                                     {"JOINTS_0", 1},
                                     {"JOINTS_1", 2},
                                     {"WEIGHTS_0", 3},
                                     {"WEIGHTS_1", 4}}}}}}}});
  doc["nodes"] = Json::array({{{"mesh", 0}, {"skin", 0}},
                              {{"children", {2}}, {"name", "hip"}},
                              {{"translation", {0, 1, 0}}, {"name", "knee"}},
                              {{"mesh", 0}, {"skin", 0}, {"name", "copy"}}});
  doc["skins"] = Json::array({{{"joints", {1, 2}}, {"skeleton", 1}}});
  doc["scenes"] = Json::array({{{"nodes", {0, 1, 3}}}});
  return doc;
}

TEST_CASE("gltf import: two joint sets, renormalised weights, skin without IBMs, instancing",
          "[gltf][import]") {
  TempDir dir;
  Bytes bin;
  const Asset asset = MustImport(dir.Write("skin.gltf", TwoSetSkin(&bin, 1).dump()));
  const AssetPrimitive& prim = asset.meshes.at(0).primitives.at(0);
  REQUIRE(prim.joints.size() == 2);
  REQUIRE(prim.weights.size() == 2);
  CHECK(prim.joints[0][0] == glm::u16vec4(0, 1, 0, 0));
  CHECK(prim.joints[1][0] == glm::u16vec4(1, 0, 0, 0));
  CHECK(prim.joints[0][2] == glm::u16vec4(1, 0, 0, 0));
  // Vertex 0: 0.5 + 0.25 + 255/255 = 1.75 over both sets.
  CHECK(prim.weights[0][0] == glm::vec4(float(0.5 / 1.75), float(0.25 / 1.75), 0, 0));
  CHECK(prim.weights[1][0] == glm::vec4(float(1.0 / 1.75), 0, 0, 0));
  // Vertex 1: all zero stays zero. Vertex 2: already 1.
  CHECK(prim.weights[0][1] == glm::vec4(0.0f));
  CHECK(prim.weights[1][1] == glm::vec4(0.0f));
  CHECK(prim.weights[0][2] == glm::vec4(1, 0, 0, 0));
  CHECK(prim.weights[1][2] == glm::vec4(0.0f));

  REQUIRE(asset.skins.size() == 1);
  const AssetSkin& skin = asset.skins[0];
  CHECK(skin.joints == std::vector<Index>{1, 2});
  CHECK(skin.skeleton == 1);
  CHECK_FALSE(skin.has_inverse_bind_matrices);
  REQUIRE(skin.inverse_bind_matrices.size() == 2);
  CHECK(skin.inverse_bind_matrices[0] == glm::mat4(1.0f));
  CHECK(skin.inverse_bind_matrices[1] == glm::mat4(1.0f));

  REQUIRE(asset.meshes.size() == 1);  // one mesh, two nodes drawing it
  CHECK(asset.nodes.at(0).mesh == 0);
  CHECK(asset.nodes.at(3).mesh == 0);
  CHECK(asset.nodes.at(3).skin == 0);
  CHECK(asset.nodes.at(2).parent == 1);
  CHECK(asset.nodes.at(1).children == std::vector<Index>{2});
  CHECK(asset.nodes.at(0).parent == kInvalidIndex);
  CHECK(asset.scenes.at(0).nodes == std::vector<Index>{0, 1, 3});
}

TEST_CASE("gltf import: animation samplers (CUBICSPLINE, STEP, morph weights)", "[gltf][import]") {
  TempDir dir;
  Bytes bin;
  const std::size_t p = bin.Put<float>({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const std::size_t times = bin.Put<float>({0.0f, 0.5f, 1.25f});
  // CUBICSPLINE translation: per keyframe in-tangent, value, out-tangent (VEC3 each).
  std::vector<float> cubic;
  for (int i = 0; i < 27; ++i) cubic.push_back(float(i) * 0.5f - 3.0f);
  const std::size_t tr = bin.size();
  for (float v : cubic) bin.Put<float>({v});
  // STEP rotation as normalized i16 quaternions (x y z w).
  const std::size_t rot = bin.Put<std::int16_t>({0, 0, 0, 32767, 0, 32767, 0, 0, 0, 0, -32767, 0});
  // LINEAR weights for 2 morph targets: 3 keyframes x 2.
  const std::size_t wts = bin.Put<float>({0, 1, 0.5f, 0.5f, 1, 0});
  Json doc = Document(bin);
  doc["bufferViews"] = {View(p, 36), View(times, 12), View(tr, 108), View(rot, 24), View(wts, 24)};
  Json in = Accessor(1, kFloat, 3, "SCALAR");
  in["min"] = {0};
  in["max"] = {1.25};
  Json rq = Accessor(3, kShort, 3, "VEC4");
  rq["normalized"] = true;
  doc["accessors"] = {Accessor(0, kFloat, 3, "VEC3"),   in,
                      Accessor(2, kFloat, 9, "VEC3"),   rq,
                      Accessor(4, kFloat, 6, "SCALAR"), Accessor(-1, kFloat, 3, "VEC3")};
  doc["accessors"][0]["min"] = {0, 0, 0};
  doc["accessors"][0]["max"] = {1, 1, 0};
  doc["meshes"] = Json::array({{{"primitives",
                                 {{{"attributes", {{"POSITION", 0}}},
                                   {"targets", {{{"POSITION", 5}}, {{"POSITION", 5}}}}}}}}});
  doc["nodes"] = Json::array({{{"mesh", 0}, {"children", {1}}}, {{"name", "joint"}}});
  doc["animations"] =
      Json::array({{{"name", "clip"},
                    {"samplers",
                     {{{"input", 1}, {"output", 2}, {"interpolation", "CUBICSPLINE"}},
                      {{"input", 1}, {"output", 3}, {"interpolation", "STEP"}},
                      {{"input", 1}, {"output", 4}}}},
                    {"channels",
                     {{{"sampler", 0}, {"target", {{"node", 1}, {"path", "translation"}}}},
                      {{"sampler", 1}, {"target", {{"node", 1}, {"path", "rotation"}}}},
                      {{"sampler", 2}, {"target", {{"node", 0}, {"path", "weights"}}}}}}}});
  const Asset asset = MustImport(dir.Write("anim.gltf", doc.dump()));
  REQUIRE(asset.animations.size() == 1);
  const AssetAnimation& anim = asset.animations[0];
  CHECK(anim.name == "clip");
  CHECK(anim.Duration() == Approx(1.25).margin(0));
  REQUIRE(anim.samplers.size() == 3);
  const AssetAnimationSampler& s0 = anim.samplers[0];
  CHECK(s0.interpolation == Interpolation::kCubicSpline);
  CHECK(s0.components == 3);
  CHECK(s0.times == std::vector<float>{0.0f, 0.5f, 1.25f});
  CHECK(s0.values == cubic);  // 3 keyframes x (in, value, out) x 3, in file order
  const AssetAnimationSampler& s1 = anim.samplers[1];
  CHECK(s1.interpolation == Interpolation::kStep);
  CHECK(s1.components == 4);
  CHECK(s1.values == std::vector<float>{0, 0, 0, 1, 0, 1, 0, 0, 0, 0, -1, 0});
  const AssetAnimationSampler& s2 = anim.samplers[2];
  CHECK(s2.interpolation == Interpolation::kLinear);
  CHECK(s2.components == 2);
  CHECK(s2.values == std::vector<float>{0, 1, 0.5f, 0.5f, 1, 0});
  REQUIRE(anim.channels.size() == 3);
  CHECK(anim.channels[0].node == 1);
  CHECK(anim.channels[0].path == AnimationPath::kTranslation);
  CHECK(anim.channels[1].path == AnimationPath::kRotation);
  CHECK(anim.channels[2].sampler == 2);
  CHECK(anim.channels[2].node == 0);
  CHECK(anim.channels[2].path == AnimationPath::kWeights);
}

TEST_CASE("gltf import: images stay encoded bytes; materials, textures, samplers",
          "[gltf][import]") {
  TempDir dir;
  const std::string png =
      std::string("\x89PNG\r\n\x1a\n", 8) + std::string("not really \0 a png", 18);
  const std::string jpeg = std::string("\xFF\xD8\xFF\xE0", 4) + "jpeg body\x01\x02";
  const std::string webp = std::string("RIFF\x10\0\0\0WEBPVP8 ", 16) + "webp body";
  dir.Write("tex%20one.webp", std::string());  // a decoy: the URI is percent-decoded
  dir.Write("tex one.webp", webp);
  Bytes bin;
  bin.Put<float>({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const std::size_t jv = bin.PutRaw(jpeg);
  bin.Align4();
  Json doc = Document(bin);
  doc["bufferViews"] = {View(0, 36), View(jv, jpeg.size())};
  doc["accessors"] = {Accessor(0, kFloat, 3, "VEC3")};
  doc["accessors"][0]["min"] = {0, 0, 0};
  doc["accessors"][0]["max"] = {1, 1, 0};
  doc["images"] = {{{"uri", "data:image/png;base64," + Base64(png)}, {"name", "png"}},
                   {{"bufferView", 1}, {"mimeType", "image/jpeg"}},
                   {{"uri", "tex%20one.webp"}}};
  doc["samplers"] = {{{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 33071}}};
  doc["textures"] = {{{"source", 0}, {"sampler", 0}}, {{"source", 1}}, {{"source", 2}}};
  const Json material = Json::parse(R"({
    "name": "skin", "doubleSided": true, "alphaMode": "MASK", "alphaCutoff": 0.25,
    "pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 0.25, 1],
      "baseColorTexture": {"index": 0, "texCoord": 1}, "metallicFactor": 0},
    "normalTexture": {"index": 1, "scale": 0.5},
    "emissiveTexture": {"index": 2}, "emissiveFactor": [0.1, 0.2, 0.3],
    "extensions": {"KHR_materials_unlit": {}}, "extras": {"note": [1, 2]}})");
  doc["materials"] = Json::array({material});
  doc["meshes"] =
      Json::array({{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"material", 0}}}}}});
  doc["nodes"] = Json::array({{{"mesh", 0}}});
  const Asset asset = MustImport(dir.Write("images.gltf", doc.dump()));
  REQUIRE(asset.images.size() == 3);
  CHECK(asset.images[0].bytes == png);
  CHECK(asset.images[0].mime_type == "image/png");
  CHECK(asset.images[0].name == "png");
  CHECK(asset.images[1].bytes == jpeg);
  CHECK(asset.images[1].mime_type == "image/jpeg");
  CHECK(asset.images[2].bytes == webp);
  CHECK(asset.images[2].mime_type == "image/webp");  // guessed from the magic bytes
  REQUIRE(asset.textures.size() == 3);
  CHECK(asset.textures[0].image == 0);
  CHECK(asset.textures[0].sampler == 0);
  CHECK(asset.textures[1].sampler == kInvalidIndex);
  REQUIRE(asset.samplers.size() == 1);
  CHECK(asset.samplers[0].mag_filter == 9729);
  CHECK(asset.samplers[0].min_filter == 9987);
  CHECK(asset.samplers[0].wrap_s == 33071);
  CHECK(asset.samplers[0].wrap_t == 10497);
  REQUIRE(asset.materials.size() == 1);
  CHECK(asset.materials[0].name == "skin");
  CHECK(Json::parse(asset.materials[0].json) == material);
  CHECK(asset.materials[0].json == material.dump());  // compact, keys sorted
  CHECK(asset.meshes.at(0).primitives.at(0).material == 0);
}

/// A GLB with a triangle in the BIN chunk and a .dsurf payload in its own bufferView.
std::string TriangleGlb(const std::string& dsurf, bool with_extension) {
  Bytes bin;
  Json doc = Triangle(&bin);
  const std::size_t d = bin.PutRaw(dsurf);
  bin.Align4();
  doc["buffers"] = Json::array({{{"byteLength", bin.size()}}});
  doc["bufferViews"].push_back(View(d, dsurf.size()));
  if (with_extension) {
    doc["extensionsUsed"] = Json::array({kDsurfGltfExtension});
    doc["extensions"][kDsurfGltfExtension] = {{"bufferView", 2}};
  }
  return MakeGlb(doc.dump(), bin.str());
}

TEST_CASE("gltf import: hand-built GLB with a DERMIS_displaced_surface payload", "[gltf][import]") {
  TempDir dir;
  const std::string payload = std::string("DSRF\0\x01\x02", 7) + "payload";
  std::string dsurf = "stale";
  const Asset asset = MustImport(dir.Write("tri.glb", TriangleGlb(payload, true)), &dsurf);
  CHECK(dsurf == payload);
  CHECK(asset.meshes.at(0).primitives.at(0).positions ==
        std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  CHECK(asset.meshes[0].primitives[0].indices == std::vector<std::uint32_t>{0, 1, 2});
  MustImport(dir.Write("plain.glb", TriangleGlb(payload, false)), &dsurf);
  CHECK(dsurf.empty());
}

TEST_CASE("gltf import: broken GLB containers", "[gltf][import][errors]") {
  TempDir dir;
  const std::string good = TriangleGlb("abcd", true);
  SECTION("truncated") {
    const std::string path = dir.Write("truncated.glb", good.substr(0, good.size() / 2));
    ExpectError(path, "length");
  }
  SECTION("shorter than a header") { ExpectError(dir.Write("tiny.glb", "glTF\x02"), "truncated"); }
  SECTION("garbage bytes") {
    std::string garbage;
    std::mt19937 rng(7);
    for (int i = 0; i < 500; ++i) garbage.push_back(char(rng() & 0xFF));
    ExpectError(dir.Write("garbage.glb", garbage), "bad magic");
  }
  SECTION("JSON chunk longer than the file") {
    std::string bad = good;
    const std::uint32_t huge = 0x7FFFFFF0u;
    std::memcpy(&bad[12], &huge, 4);
    ExpectError(dir.Write("chunk.glb", bad), "JSON chunk");
  }
  SECTION("BIN chunk longer than the file") {
    std::string bad = good;
    std::uint32_t json_length = 0;
    std::memcpy(&json_length, &bad[12], 4);
    const std::uint32_t huge = 0xFFFFFFF0u;
    std::memcpy(&bad[20 + json_length], &huge, 4);
    ExpectError(dir.Write("bin.glb", bad), "BIN chunk");
  }
  SECTION("dsurf bufferView out of range") {
    Bytes bin;
    Json doc = Triangle(&bin);
    doc["buffers"] = Json::array({{{"byteLength", bin.size()}}});
    doc["extensions"][kDsurfGltfExtension] = {{"bufferView", 9}};
    Asset asset;
    std::string dsurf;
    const Status s =
        ImportGltf(dir.Write("dsurf.glb", MakeGlb(doc.dump(), bin.str())), &asset, &dsurf);
    CHECK_FALSE(s.ok());
    CHECK(s.message().find("dsurf.glb: /extensions/DERMIS_displaced_surface/bufferView") !=
          std::string::npos);
  }
}

TEST_CASE("gltf import: malformed documents name the file and the JSON pointer",
          "[gltf][import][errors]") {
  TempDir dir;
  Bytes bin;
  Json doc = Triangle(&bin);
  SECTION("JSON syntax error") {
    std::string text = doc.dump();
    text.insert(text.size() - 1, ",]");
    const std::string path = dir.Write("syntax.gltf", text);
    ExpectError(path, "invalid JSON");
    ExpectError(path, "parse error");
  }
  SECTION("accessor out of bufferView bounds") {
    doc["accessors"][0]["count"] = 4;
    ExpectError(dir.Write("bounds.gltf", doc.dump()), "/accessors/0: byteOffset 0 + 4 elements");
  }
  SECTION("accessor byteOffset out of bounds") {
    doc["accessors"][1]["byteOffset"] = 2;
    ExpectError(dir.Write("offset.gltf", doc.dump()), "/accessors/1:");
  }
  SECTION("bufferView out of buffer bounds") {
    doc["bufferViews"][1]["byteLength"] = 400;
    ExpectError(dir.Write("view.gltf", doc.dump()), "/bufferViews/1:");
  }
  SECTION("byteStride smaller than the element") {
    doc["bufferViews"][0]["byteStride"] = 8;
    ExpectError(dir.Write("stride.gltf", doc.dump()), "/bufferViews/0/byteStride");
  }
  SECTION("index >= vertex count") {
    doc["accessors"][0]["count"] = 2;
    ExpectError(dir.Write("index.gltf", doc.dump()), "/meshes/0/primitives/0/indices");
  }
  SECTION("number out of double range (JSON cannot hold NaN or infinity)") {
    std::string text = doc.dump();
    const std::string from = R"({"mesh":0})";
    text.replace(text.find(from), from.size(),
                 R"({"mesh":0,"matrix":[1,0,0,0,0,1,0,0,0,0,1e999,0,0,0,0,1]})");
    ExpectError(dir.Write("inf.gltf", text), "invalid JSON");
    ExpectError(dir.Write("inf.gltf", text), "1e999");
  }
  SECTION("node matrix of 15 numbers") {
    doc["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0};
    ExpectError(dir.Write("matrix.gltf", doc.dump()), "/nodes/0/matrix: has 15 numbers");
  }
  SECTION("NaN in an inverse bind matrix") {
    Bytes b;
    Json d = Triangle(&b);
    float m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    m[13] = std::nanf("");
    const std::size_t at = b.size();
    for (float v : m) b.Put<float>({v});
    d["buffers"][0] = {{"byteLength", b.size()}, {"uri", DataUri(b.str())}};
    d["bufferViews"].push_back(View(at, 64));
    d["accessors"].push_back(Accessor(2, kFloat, 1, "MAT4"));
    d["nodes"].push_back({{"name", "joint"}});
    d["skins"] = Json::array({{{"joints", {1}}, {"inverseBindMatrices", 2}}});
    d["scenes"][0]["nodes"] = {0, 1};
    ExpectError(dir.Write("nan.gltf", d.dump()), "/accessors/2: element 0 component 13");
    ExpectError(dir.Write("nan.gltf", d.dump()), "/skins/0/inverseBindMatrices");
  }
  SECTION("cyclic node graph") {
    doc["nodes"] = Json::array({{{"mesh", 0}}, {{"children", {2}}}, {{"children", {1}}}});
    ExpectError(dir.Write("cycle.gltf", doc.dump()), "/children/0: node ");
    ExpectError(dir.Write("cycle.gltf", doc.dump()), "cycle");
  }
  SECTION("node with two parents") {
    doc["nodes"] =
        Json::array({{{"mesh", 0}, {"children", {2}}}, {{"children", {2}}}, Json::object()});
    doc["scenes"][0]["nodes"] = {0, 1};
    ExpectError(dir.Write("parents.gltf", doc.dump()),
                "/nodes/1/children/0: node 2 has two parents (0 and 1)");
  }
  SECTION("missing external buffer") {
    doc["buffers"][0]["uri"] = "missing.bin";
    const std::string path = dir.Write("external.gltf", doc.dump());
    Asset asset;
    CHECK(ImportGltf(path, &asset).code() == StatusCode::kIoError);
    ExpectError(path, "/buffers/0/uri: external buffer 'missing.bin' not found");
  }
  SECTION("missing external image") {
    doc["images"] = Json::array({{{"uri", "nowhere.png"}}});
    ExpectError(dir.Write("image.gltf", doc.dump()), "/images/0/uri: external image 'nowhere.png'");
  }
  SECTION("image bufferView outside its buffer") {
    doc["bufferViews"].push_back(View(4, 4000));
    doc["images"] = Json::array({{{"bufferView", 2}, {"mimeType", "image/png"}}});
    ExpectError(dir.Write("image_view.gltf", doc.dump()),
                "/bufferViews/2: byteOffset 4 + byteLength 4000");
    ExpectError(dir.Write("image_view.gltf", doc.dump()), "(used by /images/0)");
  }
  SECTION("unreadable file") {
    Asset asset;
    const Status s = ImportGltf("/nonexistent/dir/none.gltf", &asset);
    CHECK(s.code() == StatusCode::kIoError);
    CHECK(s.message().find("none.gltf") != std::string::npos);
  }
}

TEST_CASE("gltf import: joint indices are checked against every skin drawing the mesh",
          "[gltf][import][errors]") {
  TempDir dir;
  SECTION("joint 2 of a 2-joint skin") {
    Bytes bin;
    ExpectError(dir.Write("joints.gltf", TwoSetSkin(&bin, 2).dump()),
                "/meshes/0/primitives/0/attributes/JOINTS_1: vertex 0 has joint index 2");
  }
  SECTION("fine for one instance, out of range for the other") {
    Bytes bin;
    Json doc = TwoSetSkin(&bin, 1);
    doc["skins"].push_back({{"joints", {1}}});
    doc["nodes"][3]["skin"] = 1;
    ExpectError(dir.Write("instances.gltf", doc.dump()),
                "/meshes/0/primitives/0/attributes/JOINTS_0");
  }
}

TEST_CASE("gltf import: existing external buffer next to the .gltf", "[gltf][import]") {
  TempDir dir;
  Bytes bin;
  Json doc = Triangle(&bin);
  dir.Write("tri data.bin", bin.str());
  doc["buffers"][0]["uri"] = "tri%20data.bin";
  const Asset asset = MustImport(dir.Write("external_ok.gltf", doc.dump()));
  CHECK(asset.meshes.at(0).primitives.at(0).positions.at(1) == glm::vec3(1, 0, 0));
}

// ---- the shared sample characters (facts from the README of the shared data folder) ----

struct SampleFacts {
  const char* file;
  std::size_t nodes, vertices, triangles, joints, animations;
};

TEST_CASE("gltf import: shared sample characters", "[gltf][import][data]") {
  const std::string root = "../shared/data/gltf/";
  if (!fs::exists(root + "Fox.glb")) {
    WARN("skipped: " << root << " not found (run from the repository root)");
    return;
  }
  const SampleFacts facts[] = {{"SimpleSkin.gltf", 3, 10, 8, 2, 1},
                               {"RiggedSimple.glb", 5, 160, 188, 2, 1},
                               {"RiggedFigure.glb", 22, 370, 256, 19, 1},
                               {"Fox.glb", 26, 1728, 576, 24, 3},
                               {"CesiumMan.glb", 22, 3273, 4672, 19, 1}};
  for (const SampleFacts& f : facts) {
    INFO(f.file);
    const Asset asset = MustImport(root + f.file);
    CHECK(asset.nodes.size() == f.nodes);
    REQUIRE(asset.skins.size() == 1);
    CHECK(asset.skins[0].joints.size() == f.joints);
    CHECK(asset.skins[0].has_inverse_bind_matrices);
    CHECK(asset.animations.size() == f.animations);
    std::size_t vertices = 0, triangles = 0;
    for (const AssetMesh& mesh : asset.meshes) {
      for (const AssetPrimitive& p : mesh.primitives) {
        vertices += p.positions.size();
        triangles += (p.indices.empty() ? p.positions.size() : p.indices.size()) / 3;
        REQUIRE(p.weights.size() == 1);
        for (std::size_t v = 0; v < p.positions.size(); ++v) {
          const glm::vec4 w = p.weights[0][v];
          const double sum = double(w.x) + double(w.y) + double(w.z) + double(w.w);
          if (std::abs(sum - 1.0) > 1e-6) FAIL("vertex " << v << " weights sum to " << sum);
        }
      }
    }
    CHECK(vertices == f.vertices);
    CHECK(triangles == f.triangles);
  }
  const std::map<std::string, double> durations = {{"SimpleSkin.gltf", 5.5},
                                                   {"RiggedSimple.glb", 2.083},
                                                   {"RiggedFigure.glb", 1.25},
                                                   {"CesiumMan.glb", 2.0}};
  for (const auto& [file, duration] : durations) {
    const Asset asset = MustImport(root + file);
    CHECK(asset.animations.at(0).Duration() == Approx(duration).margin(1e-3));
  }

  const Asset fox = MustImport(root + "Fox.glb");
  const std::map<std::string, double> clips = {{"Survey", 3.417}, {"Walk", 0.708}, {"Run", 1.158}};
  for (const AssetAnimation& anim : fox.animations) {
    INFO(anim.name);
    REQUIRE(clips.count(anim.name) == 1);
    CHECK(anim.Duration() == Approx(clips.at(anim.name)).margin(1e-3));
  }
  CHECK(fox.generator.empty());
  CHECK_FALSE(fox.copyright.empty());
  REQUIRE(fox.images.size() == 1);
  CHECK(fox.images[0].bytes.size() == 26764);
  CHECK(fox.images[0].bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0);
  CHECK(fox.images[0].mime_type == "image/png");

  const Asset man = MustImport(root + "CesiumMan.glb");
  REQUIRE(man.images.size() == 1);
  CHECK(man.images[0].bytes.size() == 209908);
  CHECK(man.images[0].bytes.compare(0, 3, "\xFF\xD8\xFF") == 0);
  CHECK(man.images[0].mime_type == "image/jpeg");
  REQUIRE(man.materials.size() >= 1);
  CHECK(Json::parse(man.materials[0].json).is_object());
}

}  // namespace
}  // namespace dermis

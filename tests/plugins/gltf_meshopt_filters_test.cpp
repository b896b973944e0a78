// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The three filters of EXT_meshopt_compression on import (docs/gltf-compression.md, "Import"),
// against files written here with meshoptimizer's own encoders, as gltfpack writes them:
// CesiumMan's normals with meshopt_encodeFilterOct (8 bits in int8, gltfpack's default), its
// joint rotations with meshopt_encodeFilterQuat (12 bits in int16) and its positions with
// meshopt_encodeFilterExp (16-bit mantissas). Each decoded value must equal meshoptimizer's
// own decoding of the same bytes read by the glTF rules for normalized integers, and lie
// within the filter's precision of the original.
#include <meshoptimizer.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "dermis/offline/character/skin_transfer.h"
#include "dermis/plugins/gltf.h"
#include "support/external_checks.h"
#include "support/temp_files.h"

namespace dermis {
namespace {

using nlohmann::json;

/// A GLB of `doc` and `bin` (glTF 2.0 section 4.4: 12-byte header, JSON chunk padded with
/// spaces, BIN chunk padded with zeros).
std::string Glb(const json& doc, std::string bin) {
  std::string text = doc.dump();
  while (text.size() % 4 != 0) text += ' ';
  while (bin.size() % 4 != 0) bin += '\0';
  std::string out;
  auto u32 = [&out](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out += static_cast<char>((v >> (8 * i)) & 0xffu);
  };
  u32(0x46546C67u);  // "glTF"
  u32(2);
  u32(static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
  u32(static_cast<std::uint32_t>(text.size()));
  u32(0x4E4F534Au);  // "JSON"
  out += text;
  u32(static_cast<std::uint32_t>(bin.size()));
  u32(0x004E4942u);  // "BIN\0"
  out += bin;
  return out;
}

/// One filtered attribute stream: its filtered bytes (what meshopt_decodeVertexBuffer gives
/// back, before the filter is undone) and the view's layout.
struct Stream {
  std::string filtered;
  std::size_t count = 0, stride = 0;
  const char* filter = "NONE";
};

/// The bufferView (uncompressed layout in the fallback buffer 1, meshopt data in buffer 0)
/// of `s`; its encoded bytes are appended to `bin`.
json MeshoptView(const Stream& s, std::size_t* fallback_offset, std::string* bin) {
  std::vector<unsigned char> encoded(meshopt_encodeVertexBufferBound(s.count, s.stride));
  encoded.resize(meshopt_encodeVertexBuffer(encoded.data(), encoded.size(), s.filtered.data(),
                                            s.count, s.stride));
  REQUIRE(!encoded.empty());
  while (bin->size() % 4 != 0) *bin += '\0';
  const std::size_t offset = bin->size();
  bin->append(reinterpret_cast<const char*>(encoded.data()), encoded.size());
  json ext = {{"buffer", 0},
              {"byteOffset", offset},
              {"byteLength", encoded.size()},
              {"byteStride", s.stride},
              {"count", s.count},
              {"mode", "ATTRIBUTES"}};
  if (std::strcmp(s.filter, "NONE") != 0) ext["filter"] = s.filter;
  json view = {{"buffer", 1},
               {"byteOffset", *fallback_offset},
               {"byteLength", s.count * s.stride},
               {"byteStride", s.stride},
               {"extensions", {{"EXT_meshopt_compression", ext}}}};
  *fallback_offset += s.count * s.stride;
  return view;
}

/// meshoptimizer's decoding of a filtered stream (the reference).
std::string Unfiltered(const Stream& s) {
  std::string out = s.filtered;
  if (std::strcmp(s.filter, "OCTAHEDRAL") == 0)
    meshopt_decodeFilterOct(out.data(), s.count, s.stride);
  if (std::strcmp(s.filter, "QUATERNION") == 0)
    meshopt_decodeFilterQuat(out.data(), s.count, s.stride);
  if (std::strcmp(s.filter, "EXPONENTIAL") == 0)
    meshopt_decodeFilterExp(out.data(), s.count, s.stride);
  return out;
}

/// glTF's normalized integers as floats (glTF 2.0 section 3.11): max(c / 127, -1), max(c /
/// 32767, -1).
float Int8Unorm(const std::string& bytes, std::size_t i) {
  return std::max(static_cast<float>(static_cast<std::int8_t>(bytes[i])) / 127.0f, -1.0f);
}
float Int16Unorm(const std::string& bytes, std::size_t i) {
  std::int16_t v;
  std::memcpy(&v, bytes.data() + i, 2);
  return std::max(static_cast<float>(v) / 32767.0f, -1.0f);
}

TEST_CASE(
    "meshopt OCTAHEDRAL, QUATERNION and EXPONENTIAL filters decode CesiumMan as written "
    "by meshoptimizer's encoders",
    "[gltf][compression][meshopt][data]") {
  const std::string source = std::string(test::kSharedGltfDir) + "CesiumMan.glb";
  if (!std::filesystem::exists(source)) {
    WARN("skipped: " << source << " is absent (../shared/data)");
    return;
  }
  Asset original;
  REQUIRE(ImportGltf(source, &original).ok());
  const AssetPrimitive& prim = original.meshes.at(0).primitives.at(0);
  REQUIRE(!prim.normals.empty());
  const std::size_t n = prim.positions.size();
  // The longest rotation sampler of the first clip.
  REQUIRE(!original.animations.empty());
  const AssetAnimationSampler* rot = nullptr;
  for (const AssetAnimationChannel& c : original.animations[0].channels) {
    const AssetAnimationSampler& s =
        original.animations[0].samplers.at(static_cast<std::size_t>(c.sampler));
    if (c.path == AnimationPath::kRotation && (!rot || s.times.size() > rot->times.size()))
      rot = &s;
  }
  REQUIRE(rot != nullptr);
  const std::size_t keys = rot->times.size();
  REQUIRE(rot->values.size() == keys * 4);

  // The three streams, filtered by meshoptimizer's encoders.
  Stream normals{std::string(n * 4, '\0'), n, 4, "OCTAHEDRAL"};
  std::vector<float> n4(n * 4);
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) n4[4 * i + k] = prim.normals[i][k];
    n4[4 * i + 3] = 1.0f;
  }
  meshopt_encodeFilterOct(normals.filtered.data(), n, 4, 8, n4.data());
  Stream rotations{std::string(keys * 8, '\0'), keys, 8, "QUATERNION"};
  meshopt_encodeFilterQuat(rotations.filtered.data(), keys, 8, 12, rot->values.data());
  Stream positions{std::string(n * 12, '\0'), n, 12, "EXPONENTIAL"};
  std::vector<float> p3(n * 3);
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) p3[3 * i + k] = prim.positions[i][k];
  }
  meshopt_encodeFilterExp(positions.filtered.data(), n, 12, 16, p3.data());

  // A gltfpack-style file: one mesh and one node animated by the rotation channel.
  std::string bin;
  std::size_t fallback = 0;
  json views = json::array();
  views.push_back(MeshoptView(positions, &fallback, &bin));
  views.push_back(MeshoptView(normals, &fallback, &bin));
  views.push_back(MeshoptView(rotations, &fallback, &bin));
  while (bin.size() % 4 != 0) bin += '\0';
  const std::size_t times_offset = bin.size();
  bin.append(reinterpret_cast<const char*>(rot->times.data()), keys * 4);
  views.push_back({{"buffer", 0}, {"byteOffset", times_offset}, {"byteLength", keys * 4}});
  std::vector<std::uint32_t> indices = PrimitiveTriangles(prim);
  const std::size_t index_offset = bin.size();
  bin.append(reinterpret_cast<const char*>(indices.data()), indices.size() * 4);
  views.push_back(
      {{"buffer", 0}, {"byteOffset", index_offset}, {"byteLength", indices.size() * 4}});
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const glm::vec3& p : prim.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const json doc = {
      {"asset", {{"version", "2.0"}}},
      {"extensionsUsed", {"EXT_meshopt_compression", "KHR_mesh_quantization"}},
      {"extensionsRequired", {"EXT_meshopt_compression", "KHR_mesh_quantization"}},
      {"buffers",
       {{{"byteLength", bin.size()}},
        {{"byteLength", fallback},
         {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}}},
      {"bufferViews", views},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5126},
         {"count", n},
         {"type", "VEC3"},
         {"min", {lo.x, lo.y, lo.z}},
         {"max", {hi.x, hi.y, hi.z}}},
        {{"bufferView", 1},
         {"componentType", 5120},
         {"normalized", true},
         {"count", n},
         {"type", "VEC3"}},
        {{"bufferView", 2},
         {"componentType", 5122},
         {"normalized", true},
         {"count", keys},
         {"type", "VEC4"}},
        {{"bufferView", 3},
         {"componentType", 5126},
         {"count", keys},
         {"type", "SCALAR"},
         {"min", {rot->times.front()}},
         {"max", {rot->times.back()}}},
        {{"bufferView", 4},
         {"componentType", 5125},
         {"count", indices.size()},
         {"type", "SCALAR"}}}},
      {"meshes",
       {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"indices", 4}}}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"scenes", {{{"nodes", {0}}}}},
      {"scene", 0},
      {"animations",
       {{{"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "rotation"}}}}}},
         {"samplers", {{{"input", 3}, {"output", 2}, {"interpolation", "LINEAR"}}}}}}}};
  test::TempDir tmp;
  const std::string file = tmp.File("filters.glb");
  {
    std::ofstream out(file, std::ios::binary);
    const std::string glb = Glb(doc, bin);
    out.write(glb.data(), static_cast<std::streamsize>(glb.size()));
  }
  Asset decoded;
  const Status s = ImportGltf(file, &decoded);
  INFO(s.message());
  REQUIRE(s.ok());
  const AssetPrimitive& got = decoded.meshes.at(0).primitives.at(0);
  REQUIRE(got.positions.size() == n);
  REQUIRE(got.normals.size() == n);
  REQUIRE(decoded.animations.size() == 1);
  const AssetAnimationSampler& got_rot = decoded.animations[0].samplers.at(0);
  REQUIRE(got_rot.values.size() == keys * 4);

  // OCTAHEDRAL: meshoptimizer's int8 output read as normalized bytes (the importer may
  // renormalise: compare directions); within the 8-bit octahedral precision of the original:
  // half a step of 2/255 on each octahedral coordinate, stretched by the map up to about 2,
  // plus the int8 rounding of the output (0.5/127 per component): under 1.5 degrees.
  const std::string ref_normals = Unfiltered(normals);
  double worst_ref = 0.0, worst_angle = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    glm::vec3 ref(Int8Unorm(ref_normals, 4 * i), Int8Unorm(ref_normals, 4 * i + 1),
                  Int8Unorm(ref_normals, 4 * i + 2));
    ref = glm::normalize(ref);
    const glm::vec3 g = glm::normalize(got.normals[i]);
    worst_ref = std::max(worst_ref, static_cast<double>(glm::length(g - ref)));
    const double c =
        std::clamp(static_cast<double>(glm::dot(g, glm::normalize(prim.normals[i]))), -1.0, 1.0);
    worst_angle = std::max(worst_angle, std::acos(c) * 180.0 / 3.14159265358979);
  }
  CHECK(worst_ref < 1e-6);
  CHECK(worst_angle < 1.5);

  // QUATERNION: meshoptimizer's int16 output read as normalized shorts; within 12-bit
  // precision of the original: the three stored components to half a step of sqrt(2)/4095
  // (|dq| <= sqrt(3) * 1.73e-4 = 3.0e-4), the int16 rounding of the output and the
  // renormalisation: 4e-4 (q and -q are the same rotation).
  const std::string ref_rot = Unfiltered(rotations);
  double worst_rot_ref = 0.0, worst_rot = 0.0;
  for (std::size_t i = 0; i < keys; ++i) {
    glm::vec4 ref, g, o;
    for (int k = 0; k < 4; ++k) {
      ref[k] = Int16Unorm(ref_rot, 8 * i + 2 * static_cast<std::size_t>(k));
      g[k] = got_rot.values[4 * i + static_cast<std::size_t>(k)];
      o[k] = rot->values[4 * i + static_cast<std::size_t>(k)];
    }
    ref = glm::normalize(ref);
    g = glm::normalize(g);
    worst_rot_ref = std::max(worst_rot_ref, static_cast<double>(glm::length(g - ref)));
    worst_rot =
        std::max(worst_rot, static_cast<double>(std::min(glm::length(g - o), glm::length(g + o))));
  }
  CHECK(worst_rot_ref < 1e-6);
  CHECK(worst_rot < 4e-4);

  // EXPONENTIAL: bit for bit meshoptimizer's floats; each component within half a step of the
  // 16-bit mantissa the vector's components share: the step is 2^(e - 15) with e the largest
  // frexp() exponent of the three (that of 0 is 0, so a vector with a zero component gets
  // steps of 2^-15: meshoptimizer 0.18's encoder).
  const std::string ref_pos = Unfiltered(positions);
  std::size_t exact = 0;
  for (std::size_t i = 0; i < n; ++i) {
    float ref[3];
    std::memcpy(ref, ref_pos.data() + 12 * i, 12);
    int e = -100;
    for (int k = 0; k < 3; ++k) {
      int ek = 0;
      std::frexp(p3[3 * i + static_cast<std::size_t>(k)], &ek);
      e = std::max(e, ek);
    }
    const double half_step = std::ldexp(1.0, e - 16);
    for (int k = 0; k < 3; ++k) {
      exact += got.positions[i][k] == ref[k];
      CHECK(std::fabs(static_cast<double>(got.positions[i][k]) - p3[3 * i + k]) <= half_step);
    }
  }
  CHECK(exact == 3 * n);
  std::printf(
      "meshopt filters on CesiumMan: normals (oct, 8 bits) %.3g degrees at most, rotations "
      "(quat, 12 bits) |q - q'| %.3g at most, positions (exp, 16 bits) %zu of %zu components "
      "as meshoptimizer decodes them\n",
      worst_angle, worst_rot, exact, 3 * n);
}

}  // namespace
}  // namespace dermis

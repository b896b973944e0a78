// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// ExportGltf / SerializeGltf: the bytes written are read back here independently (GLB chunks,
// JSON, accessors), judged by the Khronos glTF-Validator and posed by three.js in Node
// (tests/js), and re-imported with ImportGltf.

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/gtc/epsilon.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <iterator>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "dermis/asset/asset_pose.h"
#include "dermis/plugins/gltf.h"
#include "support/external_checks.h"

namespace dermis {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace dermis::test;  // NOLINT: test support

const char* const kGltfDir = kSharedGltfDir;

// ---------------------------------------------------------------------------------------------
// An independent reader of what the exporter wrote.

std::uint32_t U32(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    v |= static_cast<std::uint32_t>(static_cast<unsigned char>(b[at + i])) << (8 * i);
  }
  return v;
}

std::string Base64Decode(const std::string& text) {
  std::string out;
  std::uint32_t acc = 0;
  int bits = 0;
  for (const char c : text) {
    int v;
    if (c >= 'A' && c <= 'Z') {
      v = c - 'A';
    } else if (c >= 'a' && c <= 'z') {
      v = c - 'a' + 26;
    } else if (c >= '0' && c <= '9') {
      v = c - '0' + 52;
    } else if (c == '+') {
      v = 62;
    } else if (c == '/') {
      v = 63;
    } else {
      break;  // '=' padding
    }
    acc = (acc << 6) | static_cast<std::uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((acc >> bits) & 0xffu));
    }
  }
  return out;
}

/// The JSON document and buffer 0 of a .glb or embedded .gltf.
struct Written {
  json doc;
  std::string bin;

  std::string View(int index) const {
    const json& v = doc["bufferViews"][static_cast<std::size_t>(index)];
    return bin.substr(v.value("byteOffset", std::size_t{0}), v["byteLength"].get<std::size_t>());
  }
  const json& Accessor(int index) const {
    return doc["accessors"][static_cast<std::size_t>(index)];
  }
  template <typename T>
  std::vector<T> Read(int accessor, std::size_t components) const {
    const json& a = Accessor(accessor);
    const std::string bytes = View(a["bufferView"].get<int>());
    const std::size_t count = a["count"].get<std::size_t>() * components;
    REQUIRE(bytes.size() >= a.value("byteOffset", std::size_t{0}) + count * sizeof(T));
    std::vector<T> out(count);
    std::memcpy(out.data(), bytes.data() + a.value("byteOffset", std::size_t{0}),
                count * sizeof(T));
    return out;
  }
};

Written ParseWritten(const std::string& bytes, bool binary) {
  Written w;
  if (binary) {
    REQUIRE(bytes.size() >= 20);
    REQUIRE(bytes.compare(0, 4, "glTF") == 0);
    REQUIRE(U32(bytes, 4) == 2u);
    REQUIRE(U32(bytes, 8) == bytes.size());
    const std::uint32_t json_length = U32(bytes, 12);
    REQUIRE(U32(bytes, 16) == 0x4E4F534Au);
    REQUIRE(json_length % 4 == 0);
    w.doc = json::parse(bytes.substr(20, json_length));
    const std::size_t bin_at = 20 + json_length;
    if (bin_at < bytes.size()) {
      REQUIRE(U32(bytes, bin_at + 4) == 0x004E4942u);
      w.bin = bytes.substr(bin_at + 8, U32(bytes, bin_at));
    }
  } else {
    w.doc = json::parse(bytes);
    if (w.doc.contains("buffers")) {
      const std::string uri = w.doc["buffers"][0]["uri"].get<std::string>();
      const std::size_t comma = uri.find(',');
      REQUIRE(uri.compare(0, 5, "data:") == 0);
      REQUIRE(comma != std::string::npos);
      w.bin = Base64Decode(uri.substr(comma + 1));
    }
  }
  if (w.doc.contains("buffers")) {
    REQUIRE(w.doc["buffers"].size() == 1);
    REQUIRE(w.bin.size() >= w.doc["buffers"][0]["byteLength"].get<std::size_t>());
  }
  return w;
}

// ---------------------------------------------------------------------------------------------
// A hand-built asset.

std::uint32_t Crc32(const std::string& bytes) {
  std::uint32_t crc = 0xffffffffu;
  for (const char ch : bytes) {
    crc ^= static_cast<unsigned char>(ch);
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

void PutBe32(std::string* out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) {
    out->push_back(static_cast<char>((v >> shift) & 0xffu));
  }
}

void PngChunk(std::string* png, const std::string& type, const std::string& data) {
  PutBe32(png, static_cast<std::uint32_t>(data.size()));
  png->append(type).append(data);
  PutBe32(png, Crc32(type + data));
}

/// A valid 1x1 RGB PNG: IHDR, one IDAT (zlib with a stored deflate block), IEND.
std::string TinyPng(unsigned char r, unsigned char g, unsigned char b) {
  std::string png("\x89PNG\r\n\x1a\n", 8);
  std::string ihdr;
  PutBe32(&ihdr, 1);
  PutBe32(&ihdr, 1);
  ihdr.append(std::string("\x08\x02\x00\x00\x00", 5));  // 8 bit RGB, no interlace
  PngChunk(&png, "IHDR", ihdr);
  const std::string raw = {'\0', static_cast<char>(r), static_cast<char>(g), static_cast<char>(b)};
  std::uint32_t a = 1, s = 0;  // Adler-32
  for (const char c : raw) {
    a = (a + static_cast<unsigned char>(c)) % 65521u;
    s = (s + a) % 65521u;
  }
  std::string zlib("\x78\x01\x01\x04\x00\xfb\xff", 7);  // header, final stored block, LEN, NLEN
  zlib += raw;
  PutBe32(&zlib, (s << 16) | a);
  PngChunk(&png, "IDAT", zlib);
  PngChunk(&png, "IEND", "");
  return png;
}

/// Expected influences of one vertex after export (joint -> weight, sums to 1).
using Influences = std::map<int, double>;

struct HandBuilt {
  Asset asset;
  std::vector<Influences> expected;  // per vertex of mesh 0, with max_influences = 4
};

HandBuilt MakeHandBuilt() {
  HandBuilt h;
  Asset& a = h.asset;
  a.source = "hand_built.test";
  a.copyright = "CC0 test asset";
  // Nodes 0..5: a chain of joints 0.5 apart along +y; 6: the skinned mesh (a root);
  // 7: a morphing triangle (a root).
  for (int i = 0; i < 6; ++i) {
    AssetNode n;
    n.name = "joint" + std::to_string(i);
    if (i > 0) {
      n.parent = i - 1;
      n.translation = glm::dvec3(0.0, 0.5, 0.0);
    }
    if (i < 5) n.children = {i + 1};
    a.nodes.push_back(n);
  }
  a.nodes[2].rotation = glm::dquat(std::cos(0.1), 0.0, 0.0, std::sin(0.1));
  AssetNode skinned;
  skinned.name = "body";
  skinned.mesh = 0;
  skinned.skin = 0;
  a.nodes.push_back(skinned);
  AssetNode morph;
  morph.name = "morph";
  morph.mesh = 1;
  morph.translation = glm::dvec3(2.0, 0.0, 0.0);
  morph.scale = glm::dvec3(1.0, 2.0, 1.0);
  a.nodes.push_back(morph);
  a.scenes.push_back({"scene", {0, 6, 7}});
  a.default_scene = 0;

  AssetSkin skin;
  skin.name = "skin";
  skin.skeleton = 0;
  for (int i = 0; i < 6; ++i) {
    skin.joints.push_back(i);
    glm::mat4 ibm(1.0f);
    ibm[3][1] = -0.5f * static_cast<float>(i);
    skin.inverse_bind_matrices.push_back(ibm);
  }
  // Rotation of joint 2 in the bind pose: its IBM is inverse(T(0,1,0) R).
  skin.inverse_bind_matrices[2] =
      glm::mat4(glm::inverse(glm::translate(glm::dmat4(1.0), glm::dvec3(0.0, 1.0, 0.0)) *
                             glm::mat4_cast(a.nodes[2].rotation)));
  for (int i = 3; i < 6; ++i) {
    skin.inverse_bind_matrices[static_cast<std::size_t>(i)] = glm::mat4(
        glm::inverse(glm::translate(glm::dmat4(1.0), glm::dvec3(0.0, 1.0, 0.0)) *
                     glm::mat4_cast(a.nodes[2].rotation) *
                     glm::translate(glm::dmat4(1.0), glm::dvec3(0.0, 0.5 * (i - 2), 0.0))));
  }
  skin.inverse_bind_matrices[1][0][3] = 1e-8f;  // a last row a hair off: written exactly 0
  a.skins.push_back(skin);

  // Mesh 0: a 2 x 4 grid of vertices along y, six triangles.
  AssetPrimitive p;
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 2; ++col) {
      p.positions.emplace_back(0.25f * static_cast<float>(col), 0.5f * static_cast<float>(row),
                               0.1f * static_cast<float>(col * row));
      p.normals.emplace_back(0.0f, 0.0f, 1.0f);
      p.tangents.emplace_back(1.0f, 0.0f, 0.0f, 1.0f);
    }
  }
  p.normals[3] = glm::vec3(0.0f);              // zero: replaced by a unit vector
  p.normals[5] = glm::vec3(0.0f, 0.0f, 2.0f);  // non-unit: renormalised
  p.texcoords.resize(1);
  p.colors.resize(1);
  for (const glm::vec3& q : p.positions) {
    p.texcoords[0].emplace_back(q.x * 4.0f, q.y / 1.5f);
    p.colors[0].emplace_back(1.0f, q.y / 1.5f, 0.5f, 1.0f);
  }
  p.indices = {0, 1, 3, 0, 3, 2, 2, 3, 5, 2, 5, 4, 4, 5, 7, 4, 7, 6};
  p.joints.assign(2, std::vector<glm::u16vec4>(8, glm::u16vec4(0)));
  p.weights.assign(2, std::vector<glm::vec4>(8, glm::vec4(0.0f)));
  const float third = 1.0f / 3.0f;
  struct Row {
    glm::u16vec4 j0;
    glm::vec4 w0;
    glm::u16vec4 j1;
    glm::vec4 w1;
  };
  const Row rows[8] = {
      {{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}},
      // Thirds: need the float32 residue fixed.
      {{0, 1, 2, 0}, {third, third, third, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}},
      // Five influences: the smallest (joint 4) is dropped, the rest renormalised.
      {{0, 1, 2, 3}, {0.3f, 0.25f, 0.2f, 0.15f}, {4, 0, 0, 0}, {0.1f, 0, 0, 0}},
      // A duplicated joint: merged into one influence.
      {{1, 0, 0, 0}, {0.5f, 0, 0, 0}, {1, 2, 0, 0}, {0.25f, 0.25f, 0, 0}},
      // Unsorted with a tie.
      {{2, 1, 0, 0}, {0.5f, 0.5f, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}},
      {{5, 4, 3, 2}, {0.1f, 0.1f, 0.1f, 0.7f}, {0, 0, 0, 0}, {0, 0, 0, 0}},
      {{3, 4, 5, 0}, {0.7f, 0.2f, 0.1f, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}},
      // Six influences, two ties at the cut: joints 4 and 5 (larger indices) dropped.
      {{0, 1, 2, 3}, {0.2f, 0.2f, 0.2f, 0.2f}, {5, 4, 0, 0}, {0.1f, 0.1f, 0, 0}},
  };
  for (std::size_t v = 0; v < 8; ++v) {
    p.joints[0][v] = rows[v].j0;
    p.weights[0][v] = rows[v].w0;
    p.joints[1][v] = rows[v].j1;
    p.weights[1][v] = rows[v].w1;
  }
  h.expected = {
      {{0, 1.0}},
      {{0, 1.0 / 3}, {1, 1.0 / 3}, {2, 1.0 / 3}},
      {{0, 0.3 / 0.9}, {1, 0.25 / 0.9}, {2, 0.2 / 0.9}, {3, 0.15 / 0.9}},
      {{1, 0.75}, {2, 0.25}},
      {{1, 0.5}, {2, 0.5}},
      {{5, 0.1}, {4, 0.1}, {3, 0.1}, {2, 0.7}},
      {{3, 0.7}, {4, 0.2}, {5, 0.1}},
      {{0, 0.25}, {1, 0.25}, {2, 0.25}, {3, 0.25}},
  };
  p.material = 0;
  AssetMesh mesh;
  mesh.name = "body";
  mesh.primitives.push_back(p);
  a.meshes.push_back(mesh);

  // Mesh 1: one non-indexed triangle with one morph target.
  AssetPrimitive t;
  t.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  AssetMorphTarget target;
  target.positions = {{0, 0, 0.5f}, {0, 0, -0.25f}, {0.125f, 0, 0}};
  t.targets.push_back(target);
  AssetMesh tri;
  tri.name = "tri";
  tri.primitives.push_back(t);
  tri.weights = {0.5f};
  a.meshes.push_back(tri);

  AssetMaterial material;
  material.name = "skin";
  material.json = R"({"name":"skin","pbrMetallicRoughness":{"baseColorTexture":{"index":0},)"
                  R"("metallicFactor":0.0,"roughnessFactor":0.75},"doubleSided":true})";
  a.materials.push_back(material);
  AssetImage image;
  image.name = "red";
  image.mime_type = "image/png";
  image.bytes = TinyPng(200, 30, 40);
  a.images.push_back(image);
  AssetSampler sampler;
  sampler.mag_filter = 9729;
  sampler.min_filter = 9987;
  sampler.wrap_s = 33071;
  a.samplers.push_back(sampler);
  a.textures.push_back({"red", 0, 0});

  AssetAnimation clip;
  clip.name = "wave";
  AssetAnimationSampler linear;  // translation of joint 1
  linear.times = {0.0f, 0.5f, 1.0f};
  linear.values = {0, 0.5f, 0, 0.2f, 0.5f, 0, 0, 0.5f, 0};
  linear.components = 3;
  AssetAnimationSampler cubic;  // rotation of joint 2: non-unit value keys, tangents kept
  cubic.times = {0.0f, 1.0f};
  cubic.interpolation = Interpolation::kCubicSpline;
  const float s04 = static_cast<float>(std::sin(0.4) * 1.01),
              c04 = static_cast<float>(std::cos(0.4) * 1.01);
  cubic.values = {0, 0, 0,    0, 0, 0, 0,   1.02f, 0, 0, 0.1f, 0,  // in, value, out
                  0, 0, 0.1f, 0, 0, 0, s04, c04,   0, 0, 0,    0};
  cubic.components = 4;
  AssetAnimationSampler step;  // scale of joint 3
  step.times = {0.0f, 0.25f};
  step.values = {1, 1, 1, 1.1f, 1, 1};
  step.components = 3;
  step.interpolation = Interpolation::kStep;
  AssetAnimationSampler weights;  // morph weight of node 7
  weights.times = {0.0f, 1.0f};
  weights.values = {0.0f, 1.0f};
  weights.components = 1;
  clip.samplers = {linear, cubic, step, weights};
  clip.channels = {{0, 1, AnimationPath::kTranslation},
                   {1, 2, AnimationPath::kRotation},
                   {2, 3, AnimationPath::kScale},
                   {3, 7, AnimationPath::kWeights}};
  a.animations.push_back(clip);
  return h;
}

/// Float32 sum of the non-zero weights in the validator's order (component, then set).
float ValidatorSum(const std::vector<std::vector<float>>& sets, std::size_t v) {
  float sum = 0.0f;
  for (std::size_t c = 0; c < 4; ++c) {
    for (const auto& set : sets) {
      if (set[4 * v + c] != 0.0f) sum = sum + set[4 * v + c];
    }
  }
  return sum;
}

/// Checks the written document of the hand-built asset against the asset (no importer).
void CheckHandBuiltDocument(const HandBuilt& h, const Written& w,
                            const GltfExportOptions& options) {
  const Asset& a = h.asset;
  const json& doc = w.doc;
  CHECK(doc["asset"]["version"] == "2.0");
  CHECK(doc["asset"]["generator"] == options.generator);
  CHECK(doc["asset"]["copyright"] == a.copyright);
  CHECK(doc["scene"] == 0);
  CHECK(doc["nodes"].size() == a.nodes.size());
  CHECK_FALSE(doc.contains("extensionsRequired"));
  // TRS only where not identity.
  CHECK_FALSE(doc["nodes"][0].contains("translation"));
  CHECK_FALSE(doc["nodes"][6].contains("translation"));
  CHECK_FALSE(doc["nodes"][6].contains("rotation"));
  CHECK_FALSE(doc["nodes"][6].contains("scale"));
  CHECK_FALSE(doc["nodes"][6].contains("matrix"));
  CHECK(doc["nodes"][1]["translation"] == json::array({0.0, 0.5, 0.0}));
  CHECK(doc["nodes"][7]["scale"] == json::array({1.0, 2.0, 1.0}));
  CHECK_FALSE(doc["nodes"][7].contains("rotation"));

  // POSITION bounds are exactly those of the float data.
  const json& prim = doc["meshes"][0]["primitives"][0];
  const json& pos = w.Accessor(prim["attributes"]["POSITION"].get<int>());
  for (int c = 0; c < 3; ++c) {
    float lo = std::numeric_limits<float>::max(), hi = -lo;
    for (const glm::vec3& q : a.meshes[0].primitives[0].positions) {
      lo = std::min(lo, q[c]);
      hi = std::max(hi, q[c]);
    }
    CHECK(pos["min"][static_cast<std::size_t>(c)].get<double>() == static_cast<double>(lo));
    CHECK(pos["max"][static_cast<std::size_t>(c)].get<double>() == static_cast<double>(hi));
  }
  const json& morph = doc["meshes"][1]["primitives"][0]["targets"][0]["POSITION"];
  CHECK(w.Accessor(morph.get<int>())["min"] == json::array({0.0, 0.0, -0.25}));
  CHECK(w.Accessor(morph.get<int>())["max"] == json::array({0.125, 0.0, 0.5}));
  CHECK(doc["meshes"][1]["weights"] == json::array({0.5}));
  CHECK_FALSE(doc["meshes"][1]["primitives"][0].contains("indices"));

  // Normals: unit, the zero one replaced.
  const std::vector<float> normals = w.Read<float>(prim["attributes"]["NORMAL"].get<int>(), 3);
  for (std::size_t v = 0; v < 8; ++v) {
    const double len = std::sqrt(double(normals[3 * v]) * normals[3 * v] +
                                 double(normals[3 * v + 1]) * normals[3 * v + 1] +
                                 double(normals[3 * v + 2]) * normals[3 * v + 2]);
    CHECK(len == Approx(1.0).margin(1e-6));
  }
  CHECK(normals[3 * 5 + 2] == 1.0f);

  // Skin weights: one set (max 4), u8 joints, expected influences, validator-exact sums.
  CHECK(prim["attributes"].contains("JOINTS_0"));
  CHECK_FALSE(prim["attributes"].contains("JOINTS_1"));
  const int joints_accessor = prim["attributes"]["JOINTS_0"].get<int>();
  CHECK(w.Accessor(joints_accessor)["componentType"] == 5121);
  const std::vector<std::uint8_t> joints = w.Read<std::uint8_t>(joints_accessor, 4);
  const std::vector<float> weights = w.Read<float>(prim["attributes"]["WEIGHTS_0"].get<int>(), 4);
  for (std::size_t v = 0; v < 8; ++v) {
    INFO("vertex " << v);
    Influences got;
    int nonzero = 0;
    for (std::size_t c = 0; c < 4; ++c) {
      const float wt = weights[4 * v + c];
      if (wt == 0.0f) {
        CHECK(joints[4 * v + c] == 0);  // padding: joint 0, weight 0
        continue;
      }
      ++nonzero;
      CHECK(got.count(joints[4 * v + c]) == 0);  // no duplicate joints
      got[joints[4 * v + c]] = wt;
    }
    REQUIRE(got.size() == h.expected[v].size());
    for (const auto& [joint, weight] : h.expected[v]) {
      REQUIRE(got.count(joint) == 1);
      CHECK(got[joint] == Approx(weight).margin(1e-6));
    }
    const float sum = ValidatorSum({weights}, v);
    CHECK(std::fabs(double(sum) - 1.0) <= 2e-7 * nonzero);
    if (v > 0) CHECK(weights[4 * v] >= weights[4 * v + 1]);  // largest first
  }

  // IBMs: last rows exactly (0, 0, 0, 1), the rest as given.
  const json& skin = doc["skins"][0];
  CHECK(skin["joints"] == json::array({0, 1, 2, 3, 4, 5}));
  CHECK(skin["skeleton"] == 0);
  const json& ibm_accessor = w.Accessor(skin["inverseBindMatrices"].get<int>());
  CHECK(ibm_accessor["type"] == "MAT4");
  CHECK_FALSE(
      doc["bufferViews"][ibm_accessor["bufferView"].get<std::size_t>()].contains("byteStride"));
  const std::vector<float> ibms = w.Read<float>(skin["inverseBindMatrices"].get<int>(), 16);
  REQUIRE(ibms.size() == 6 * 16);
  for (std::size_t j = 0; j < 6; ++j) {
    for (std::size_t c = 0; c < 4; ++c) {
      CHECK(ibms[16 * j + 4 * c + 3] == (c == 3 ? 1.0f : 0.0f));
      for (std::size_t r = 0; r < 3; ++r) {
        CHECK(ibms[16 * j + 4 * c + r] ==
              a.skins[0].inverse_bind_matrices[j][static_cast<int>(c)][static_cast<int>(r)]);
      }
    }
  }

  // Animation: interpolation names, exact input bounds, unit rotation values, tangents as given.
  const json& anim = doc["animations"][0];
  REQUIRE(anim["samplers"].size() == 4);
  CHECK(anim["samplers"][0]["interpolation"] == "LINEAR");
  CHECK(anim["samplers"][1]["interpolation"] == "CUBICSPLINE");
  CHECK(anim["samplers"][2]["interpolation"] == "STEP");
  CHECK(w.Accessor(anim["samplers"][0]["input"].get<int>())["min"] == json::array({0.0}));
  CHECK(w.Accessor(anim["samplers"][0]["input"].get<int>())["max"] == json::array({1.0}));
  CHECK(w.Accessor(anim["samplers"][2]["input"].get<int>())["max"] == json::array({0.25}));
  CHECK(w.Accessor(anim["samplers"][3]["output"].get<int>())["type"] == "SCALAR");
  const std::vector<float> rot = w.Read<float>(anim["samplers"][1]["output"].get<int>(), 4);
  REQUIRE(rot.size() == 24);
  const std::vector<float>& given = a.animations[0].samplers[1].values;
  for (std::size_t k = 0; k < 2; ++k) {
    const float* q = &rot[12 * k + 4];
    CHECK(std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2] +
                    double(q[3]) * q[3]) == Approx(1.0).margin(1e-6));
    for (std::size_t c = 0; c < 4; ++c) {
      CHECK(rot[12 * k + c] == given[12 * k + c]);          // in-tangent untouched
      CHECK(rot[12 * k + 8 + c] == given[12 * k + 8 + c]);  // out-tangent untouched
    }
  }
  CHECK(rot[12 + 6] == Approx(std::sin(0.4)).margin(1e-6));

  // The image: bytes through a bufferView, untouched.
  const json& img = doc["images"][0];
  CHECK(img["mimeType"] == "image/png");
  CHECK_FALSE(img.contains("uri"));
  CHECK(w.View(img["bufferView"].get<int>()) == a.images[0].bytes);
  CHECK(doc["textures"][0]["source"] == 0);
  CHECK(doc["textures"][0]["sampler"] == 0);
  CHECK(doc["samplers"][0]["wrapS"] == 33071);
  CHECK(doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] == 0);
  CHECK(doc["materials"][0]["pbrMetallicRoughness"]["roughnessFactor"] == 0.75);
  CHECK(doc["materials"][0]["doubleSided"] == true);

  // Every bufferView 4-byte aligned; vertex/index views carry their targets.
  for (const json& view : doc["bufferViews"]) {
    CHECK(view.value("byteOffset", 0) % 4 == 0);
  }
  CHECK(doc["bufferViews"][pos["bufferView"].get<std::size_t>()]["target"] == 34962);
  CHECK(doc["bufferViews"][w.Accessor(prim["indices"].get<int>())["bufferView"].get<std::size_t>()]
           ["target"] == 34963);
  CHECK(w.Accessor(prim["indices"].get<int>())["componentType"] == 5123);
}

TEST_CASE("SerializeGltf writes the hand-built asset by the validator's rules", "[gltf][export]") {
  const HandBuilt h = MakeHandBuilt();
  GltfExportOptions options;
  options.generator = "Dermis test";
  options.dsurf_bytes = std::string("DSURF\0bytes\xff", 12);
  TempDir tmp;
  for (const bool binary : {true, false}) {
    INFO((binary ? "glb" : "gltf"));
    std::string bytes;
    const Status s = SerializeGltf(h.asset, options, binary, &bytes);
    INFO(s.message());
    REQUIRE(s.ok());
    const Written w = ParseWritten(bytes, binary);
    CheckHandBuiltDocument(h, w, options);
    // The displaced-surface extension: a bufferView holding the bytes, used but not required.
    const json& ext = w.doc["extensions"][kDsurfGltfExtension];
    CHECK(w.View(ext["bufferView"].get<int>()) == options.dsurf_bytes);
    CHECK(w.doc["extensionsUsed"] == json::array({kDsurfGltfExtension}));

    const std::string file = tmp.File(binary ? "hand.glb" : "hand.gltf");
    WriteFile(file, bytes);
    if (!JsToolsReady()) continue;
    const ValidatorReport report = Validate(file, tmp);
    INFO(Messages(report));
    CHECK(report.errors == 0);
    CHECK(report.warnings == 0);
    CHECK(report.raw["info"]["hasSkins"] == true);
    CHECK(report.raw["info"]["hasTextures"] == true);
    CHECK(report.raw["info"]["maxInfluences"] == 4);
    // The unknown root extension is reported as information only.
    bool unsupported_info = false;
    for (const json& m : report.raw["issues"]["messages"]) {
      if (m["code"] == "UNSUPPORTED_EXTENSION") unsupported_info = m["severity"] == 2;
    }
    CHECK(unsupported_info);
  }
}

TEST_CASE("SerializeGltf keeps up to max_influences in JOINTS_n/WEIGHTS_n sets", "[gltf][export]") {
  const HandBuilt h = MakeHandBuilt();
  GltfExportOptions options;
  options.max_influences = 8;
  std::string bytes;
  REQUIRE(SerializeGltf(h.asset, options, true, &bytes).ok());
  const Written w = ParseWritten(bytes, true);
  const json& attributes = w.doc["meshes"][0]["primitives"][0]["attributes"];
  REQUIRE(attributes.contains("JOINTS_1"));
  CHECK_FALSE(attributes.contains("JOINTS_2"));
  std::vector<std::vector<float>> weights;
  std::vector<std::vector<std::uint8_t>> joints;
  for (const char* set : {"0", "1"}) {
    weights.push_back(w.Read<float>(attributes[std::string("WEIGHTS_") + set].get<int>(), 4));
    joints.push_back(w.Read<std::uint8_t>(attributes[std::string("JOINTS_") + set].get<int>(), 4));
  }
  // Vertex 7 keeps all six influences (0.2 x 4, 0.1 x 2), vertex 2 all five.
  const std::map<std::size_t, Influences> expected = {
      {7, {{0, 0.2}, {1, 0.2}, {2, 0.2}, {3, 0.2}, {4, 0.1}, {5, 0.1}}},
      {2, {{0, 0.3}, {1, 0.25}, {2, 0.2}, {3, 0.15}, {4, 0.1}}}};
  for (const auto& [v, influences] : expected) {
    INFO("vertex " << v);
    Influences got;
    int nonzero = 0;
    for (std::size_t s = 0; s < 2; ++s) {
      for (std::size_t c = 0; c < 4; ++c) {
        if (weights[s][4 * v + c] == 0.0f) continue;
        ++nonzero;
        got[joints[s][4 * v + c]] = weights[s][4 * v + c];
      }
    }
    REQUIRE(got.size() == influences.size());
    for (const auto& [joint, weight] : influences) CHECK(got[joint] == Approx(weight).margin(1e-6));
    CHECK(std::fabs(double(ValidatorSum(weights, v)) - 1.0) <= 2e-7 * nonzero);
  }
  if (!JsToolsReady()) return;
  TempDir tmp;
  WriteFile(tmp.File("eight.glb"), bytes);
  const ValidatorReport report = Validate(tmp.File("eight.glb"), tmp);
  INFO(Messages(report));
  CHECK(report.errors == 0);
  CHECK(report.warnings == 0);
  CHECK(report.raw["info"]["maxInfluences"] == 8);  // the validator counts slots: 2 sets
}

TEST_CASE("ExportGltf round-trips the hand-built asset through ImportGltf", "[gltf][export]") {
  const HandBuilt h = MakeHandBuilt();
  GltfExportOptions options;
  options.dsurf_bytes = "dsurf payload";
  TempDir tmp;
  for (const char* name : {"hand.glb", "hand.gltf"}) {
    INFO(name);
    const std::string file = tmp.File(name);
    const Status s = ExportGltf(h.asset, options, file);
    INFO(s.message());
    REQUIRE(s.ok());
    // Atomic write: only the file itself is left in the folder.
    std::size_t entries = 0;
    for (const auto& entry : fs::directory_iterator(tmp.path())) {
      CHECK(entry.path().filename().string().find(".tmp-") == std::string::npos);
      ++entries;
    }
    CHECK(entries >= 1);
    Asset back;
    std::string dsurf;
    const Status r = ImportGltf(file, &back, &dsurf);
    INFO(r.message());
    REQUIRE(r.ok());
    CHECK(dsurf == options.dsurf_bytes);
    const Asset& a = h.asset;
    CHECK(back.nodes.size() == a.nodes.size());
    CHECK(back.meshes.size() == a.meshes.size());
    CHECK(back.skins.size() == 1);
    CHECK(back.animations.size() == 1);
    CHECK(back.animations[0].channels.size() == 4);
    CHECK(back.materials.size() == 1);
    CHECK(back.textures.size() == 1);
    CHECK(back.samplers.size() == 1);
    REQUIRE(back.images.size() == 1);
    CHECK(back.images[0].bytes == a.images[0].bytes);
    CHECK(back.images[0].mime_type == "image/png");
    CHECK(back.copyright == a.copyright);
    CHECK(back.default_scene == 0);
    REQUIRE(back.meshes[0].primitives.size() == 1);
    const AssetPrimitive& p = back.meshes[0].primitives[0];
    const AssetPrimitive& q = a.meshes[0].primitives[0];
    CHECK(p.positions == q.positions);
    CHECK(p.indices == q.indices);
    CHECK(p.texcoords == q.texcoords);
    CHECK(p.colors == q.colors);
    CHECK(p.material == 0);
    REQUIRE(p.joints.size() == 1);
    REQUIRE(p.weights.size() == 1);
    for (std::size_t v = 0; v < 8; ++v) {
      for (int c = 0; c < 4; ++c) {
        const auto it = h.expected[v].find(p.joints[0][v][c]);
        if (p.weights[0][v][c] == 0.0f) continue;
        REQUIRE(it != h.expected[v].end());
        CHECK(p.weights[0][v][c] == Approx(it->second).margin(1e-6));
      }
    }
    REQUIRE(back.meshes[1].primitives.size() == 1);
    REQUIRE(back.meshes[1].primitives[0].targets.size() == 1);
    CHECK(back.meshes[1].primitives[0].targets[0].positions ==
          a.meshes[1].primitives[0].targets[0].positions);
    CHECK(back.meshes[1].weights == a.meshes[1].weights);
    const AssetSkin& skin = back.skins[0];
    CHECK(skin.joints == a.skins[0].joints);
    CHECK(skin.skeleton == 0);
    CHECK(skin.inverse_bind_matrices[1][0][3] == 0.0f);
    for (std::size_t i = 0; i < 4; ++i) {
      const AssetAnimationSampler& got = back.animations[0].samplers[i];
      const AssetAnimationSampler& want = a.animations[0].samplers[i];
      CHECK(got.times == want.times);
      CHECK(got.interpolation == want.interpolation);
      CHECK(got.values.size() == want.values.size());
    }
    for (std::size_t i = 0; i < a.nodes.size(); ++i) {
      CHECK(back.nodes[i].name == a.nodes[i].name);
      CHECK(back.nodes[i].children == a.nodes[i].children);
      CHECK(back.nodes[i].mesh == a.nodes[i].mesh);
      CHECK(back.nodes[i].skin == a.nodes[i].skin);
      CHECK(glm::all(glm::epsilonEqual(back.nodes[i].translation, a.nodes[i].translation, 1e-12)));
    }
  }
}

TEST_CASE("ExportGltf fails cleanly and leaves no file behind", "[gltf][export]") {
  TempDir tmp;
  const std::string path = tmp.File("out.glb");
  const auto no_files = [&] {
    for (const auto& entry : fs::directory_iterator(tmp.path())) {
      FAIL_CHECK("left behind: " << entry.path().string());
    }
  };
  SECTION("NaN position: the message names the source") {
    HandBuilt h = MakeHandBuilt();
    h.asset.meshes[0].primitives[0].positions[2].y = std::numeric_limits<float>::quiet_NaN();
    const Status s = ExportGltf(h.asset, GltfExportOptions(), path);
    CHECK(s.code() == StatusCode::kInvalidInput);
    CHECK(s.message().find("hand_built.test") != std::string::npos);
    no_files();
  }
  SECTION("an inverse bind matrix whose last row is off") {
    HandBuilt h = MakeHandBuilt();
    h.asset.skins[0].inverse_bind_matrices[3][2][3] = 1e-3f;
    const Status s = ExportGltf(h.asset, GltfExportOptions(), path);
    CHECK_FALSE(s.ok());
    CHECK(s.message().find("hand_built.test") != std::string::npos);
    CHECK(s.message().find("/skins/0") != std::string::npos);
    no_files();
  }
  SECTION("a material that is not JSON") {
    HandBuilt h = MakeHandBuilt();
    h.asset.materials[0].json = "{not json";
    std::string bytes;
    const Status s = SerializeGltf(h.asset, GltfExportOptions(), true, &bytes);
    CHECK(s.code() == StatusCode::kInvalidInput);
    CHECK(s.message().find("/materials/0") != std::string::npos);
  }
  SECTION("an unwritable folder") {
    const Status s =
        ExportGltf(MakeHandBuilt().asset, GltfExportOptions(), tmp.File("missing/dir/out.glb"));
    CHECK(s.code() == StatusCode::kIoError);
    no_files();
  }
  SECTION("an unknown file extension") {
    const Status s = ExportGltf(MakeHandBuilt().asset, GltfExportOptions(), tmp.File("out.obj"));
    CHECK_FALSE(s.ok());
    no_files();
  }
  SECTION("an existing file is replaced only by a complete one") {
    WriteFile(path, "old");
    HandBuilt h = MakeHandBuilt();
    h.asset.meshes[0].primitives[0].normals[0].x = std::numeric_limits<float>::infinity();
    CHECK_FALSE(ExportGltf(h.asset, GltfExportOptions(), path).ok());
    CHECK(ReadFile(path) == "old");
    REQUIRE(ExportGltf(MakeHandBuilt().asset, GltfExportOptions(), path).ok());
    std::string bytes;
    REQUIRE(SerializeGltf(MakeHandBuilt().asset, GltfExportOptions(), true, &bytes).ok());
    CHECK(ReadFile(path) == bytes);
  }
}

// ---------------------------------------------------------------------------------------------
// The shared real assets: import -> export -> validator, three.js poses, re-import.

TEST_CASE("Shared glTF characters survive ExportGltf: validator, three.js poses, re-import",
          "[gltf][export][data]") {
  if (!fs::exists(kGltfDir)) {
    WARN("skipped: ../shared/data is absent");
    return;
  }
  if (!JsToolsReady()) return;
  TempDir tmp;
  for (const char* name :
       {"SimpleSkin.gltf", "RiggedSimple.glb", "RiggedFigure.glb", "Fox.glb", "CesiumMan.glb"}) {
    INFO(name);
    const std::string source = std::string(kGltfDir) + name;
    Asset asset;
    Status s = ImportGltf(source, &asset);
    INFO(s.message());
    REQUIRE(s.ok());
    const std::string exported = tmp.File("export.glb");
    s = ExportGltf(asset, GltfExportOptions(), exported);
    INFO(s.message());
    REQUIRE(s.ok());

    const ValidatorReport before = Validate(source, tmp);
    const ValidatorReport after = Validate(exported, tmp);
    INFO(Messages(after));
    CHECK(before.errors == 0);
    CHECK(after.errors == 0);
    for (const std::string& code : after.warning_codes) {
      CHECK(before.warning_codes.count(code) == 1);
    }

    Asset back;
    s = ImportGltf(exported, &back);
    INFO(s.message());
    REQUIRE(s.ok());
    CheckSameCounts(asset, back);

    CheckThreeMatchesOurPoses(exported, back, tmp);
  }
}

}  // namespace
}  // namespace dermis

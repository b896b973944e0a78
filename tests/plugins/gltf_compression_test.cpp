// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Compressed glTF out and in (docs/gltf-compression.md) on the shared Khronos characters:
// --quantize (KHR_mesh_quantization) and --compress (EXT_meshopt_compression) exports judged by
// the Khronos validator, three.js (with its meshopt decoder) and our importer against the
// uncompressed asset; Draco files made here with Draco's encoder API; and both kinds fitted
// like the originals.
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "dermis/asset/asset_pose.h"
#include "dermis/offline/character/character_fit.h"
#include "dermis/plugins/gltf.h"
#include "support/external_checks.h"

namespace dermis {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace dermis::test;  // NOLINT: test support

const char* const kCharacters[] = {"SimpleSkin.gltf", "RiggedSimple.glb", "RiggedFigure.glb",
                                   "Fox.glb", "CesiumMan.glb"};

/// World positions of every drawn primitive, keyed by (mesh, primitive, n-th node drawing the
/// mesh), so that an asset whose meshes moved to child nodes (quantisation) compares.
using Drawn = std::map<std::tuple<Index, std::size_t, int>, std::vector<glm::dvec3>>;

Drawn Draw(const Asset& asset, int clip, double time) {
  AssetPose pose;
  if (clip < 0) {
    RestPose(asset, &pose);
  } else {
    SamplePose(asset, clip, time, &pose);
  }
  std::vector<glm::dmat4> world;
  ComputeWorldMatrices(asset, pose, &world);
  Drawn out;
  std::map<Index, int> seen;
  for (std::size_t n = 0; n < asset.nodes.size(); ++n) {
    const Index mesh = asset.nodes[n].mesh;
    if (mesh < 0) continue;
    const int k = seen[mesh]++;
    const AssetMesh& m = asset.meshes[static_cast<std::size_t>(mesh)];
    for (std::size_t p = 0; p < m.primitives.size(); ++p) {
      PosePrimitive(asset, pose, world, static_cast<Index>(n), m.primitives[p], &out[{mesh, p, k}],
                    nullptr);
    }
  }
  return out;
}

/// Largest |a - b| over every drawn vertex (CHECKs the same primitives and counts) and the
/// diagonal of `a`'s positions.
double MaxDistance(const Drawn& a, const Drawn& b, double* diagonal) {
  REQUIRE(a.size() == b.size());
  double worst = 0.0;
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& [key, pa] : a) {
    auto it = b.find(key);
    REQUIRE(it != b.end());
    REQUIRE(pa.size() == it->second.size());
    for (std::size_t i = 0; i < pa.size(); ++i) {
      worst = std::max(worst, glm::distance(pa[i], it->second[i]));
      lo = glm::min(lo, pa[i]);
      hi = glm::max(hi, pa[i]);
    }
  }
  *diagonal = glm::distance(lo, hi);
  return worst;
}

/// The largest Frobenius norm of the linear part of a world or joint matrix of the rest pose:
/// a mesh-space error e moves a drawn vertex by at most this times e.
double LargestScale(const Asset& asset) {
  AssetPose pose;
  RestPose(asset, &pose);
  std::vector<glm::dmat4> world, joints;
  ComputeWorldMatrices(asset, pose, &world);
  std::vector<glm::dmat4> all = world;
  for (const AssetSkin& skin : asset.skins) {
    ComputeJointMatrices(skin, world, &joints);
    all.insert(all.end(), joints.begin(), joints.end());
  }
  double s = 1.0;
  for (const glm::dmat4& m : all) {
    double f = 0.0;
    for (int c = 0; c < 3; ++c) f += glm::dot(glm::dvec3(m[c]), glm::dvec3(m[c]));
    s = std::max(s, std::sqrt(f));
  }
  return s;
}

/// CHECKs that `back` draws what `asset` draws at rest and along every clip, within what
/// quantisation may move (position error times the largest scale, weight error times the
/// drawn size) and 1e-6 of the diagonal of float rounding.
void CheckSameDrawing(const Asset& asset, const Asset& back, const GltfExportReport& report) {
  REQUIRE(asset.animations.size() == back.animations.size());
  const double scale = LargestScale(asset);
  for (int clip = -1; clip < static_cast<int>(asset.animations.size()); ++clip) {
    const double end = clip < 0 ? 0.0 : asset.animations[std::size_t(clip)].Duration();
    for (const double t : {0.0, 0.37 * end, end}) {
      double diagonal = 0.0;
      const double d = MaxDistance(Draw(asset, clip, t), Draw(back, clip, t), &diagonal);
      const double allowed = report.max_position_error * scale +
                             4.0 * report.max_weight_error * diagonal + 1e-6 * diagonal;
      INFO("clip " << clip << " t " << t << ": " << d << " allowed " << allowed);
      CHECK(d <= allowed);
    }
  }
}

TEST_CASE(
    "Quantized and compressed exports of the shared characters: validator, three.js, "
    "re-import",
    "[gltf][compression][data]") {
  if (!fs::exists(kSharedGltfDir)) {
    WARN("skipped: ../shared/data is absent");
    return;
  }
  if (!JsToolsReady()) return;
  TempDir tmp;
  for (const char* name : kCharacters) {
    INFO(name);
    Asset asset;
    Status s = ImportGltf(std::string(kSharedGltfDir) + name, &asset);
    INFO(s.message());
    REQUIRE(s.ok());
    // The reference: the plain export read back (float32 weights renormalised as the
    // validator wants them), which quantisation and compression must draw alike.
    std::string plain_bytes;
    REQUIRE(SerializeGltf(asset, GltfExportOptions(), true, &plain_bytes).ok());
    const std::string plain_file = tmp.File("plain.glb");
    std::ofstream(plain_file, std::ios::binary) << plain_bytes;
    Asset plain;
    REQUIRE(ImportGltf(plain_file, &plain).ok());
    const ValidatorReport source = Validate(std::string(kSharedGltfDir) + name, tmp);
    for (const auto& [quantize, compress] :
         {std::pair{true, false}, std::pair{false, true}, std::pair{true, true}}) {
      INFO("quantize " << quantize << " compress " << compress);
      GltfExportOptions options;
      options.quantize = quantize;
      options.compress = compress;
      GltfExportReport report;
      // Kept short for CI: .gltf output and three.js for the combination users ship
      // (quantize + compress); each alone is validated and read back by our importer.
      const bool both = quantize && compress;
      for (const char* ext : {".glb", ".gltf"}) {
        if (!both && std::string(ext) == ".gltf") continue;
        const std::string file = tmp.File(std::string("packed") + ext);
        s = ExportGltf(asset, options, file, &report);
        INFO(s.message());
        REQUIRE(s.ok());
        CHECK(report.quantized == quantize);
        CHECK(report.compressed == compress);
        if (quantize) {
          CHECK(report.position_bits >= 10);
          CHECK(report.position_bits <= 16);
          CHECK(report.max_position_error <= std::sqrt(3.0) / 2.0 * report.position_step * 1.0001);
          CHECK(report.max_normal_error_degrees < 0.01);
          CHECK(report.max_weight_error <= 0.5 / 65535.0 * 4.0);
        }
        if (compress) CHECK(report.bytes_after_compression <= report.bytes_before_compression);

        const ValidatorReport judged = Validate(file, tmp);
        INFO(Messages(judged));
        CHECK(judged.errors == 0);
        for (const std::string& code : judged.warning_codes) {
          CHECK(source.warning_codes.count(code) == 1);
        }
        Asset back;
        s = ImportGltf(file, &back);
        INFO(s.message());
        REQUIRE(s.ok());
        CheckSameDrawing(plain, back, report);
        if (both && std::string(ext) == ".glb") CheckThreeMatchesOurPoses(file, back, tmp);
      }
      std::string bytes;
      REQUIRE(SerializeGltf(asset, options, true, &bytes).ok());
      std::printf(
          "%-18s quantize %d compress %d: %zu -> %zu bytes (%.0f %%)\n", name, quantize, compress,
          plain_bytes.size(), bytes.size(),
          100.0 * static_cast<double>(bytes.size()) / static_cast<double>(plain_bytes.size()));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Draco: our plain export with every primitive replaced by a KHR_draco_mesh_compression
// bitstream written with Draco's encoder (as Blender and gltf-pipeline write them).

std::uint32_t U32(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(b[at + std::size_t(i)]);
  return v;
}

void PutU32(std::string* b, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b->push_back(static_cast<char>((v >> (8 * i)) & 0xFFu));
}

template <typename T, int N>
int AddDracoAttribute(draco::Mesh* mesh, draco::GeometryAttribute::Type type, draco::DataType dt,
                      const std::vector<T>& values) {
  draco::GeometryAttribute ga;
  ga.Init(type, nullptr, N, dt, false, sizeof(T), 0);
  const int id = mesh->AddAttribute(ga, true, static_cast<std::uint32_t>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i) {
    mesh->attribute(id)->SetAttributeValue(draco::AttributeValueIndex(std::uint32_t(i)),
                                           &values[i]);
  }
  return static_cast<int>(mesh->attribute(id)->unique_id());
}

/// `asset` as a GLB whose primitives are Draco-compressed (positions 14 bits, normals 10,
/// UVs 12, weights 12, joints lossless). Fails the test if the asset has morph targets.
std::string WriteDracoGlb(const Asset& asset) {
  std::string glb;
  REQUIRE(SerializeGltf(asset, GltfExportOptions(), true, &glb).ok());
  const std::size_t json_length = U32(glb, 12);
  json doc = json::parse(glb.substr(20, json_length));
  std::string bin = glb.substr(20 + json_length + 8);
  for (std::size_t m = 0; m < asset.meshes.size(); ++m) {
    for (std::size_t p = 0; p < asset.meshes[m].primitives.size(); ++p) {
      const AssetPrimitive& prim = asset.meshes[m].primitives[p];
      REQUIRE(prim.targets.empty());
      REQUIRE(prim.mode == PrimitiveMode::kTriangles);
      json& out = doc["meshes"][m]["primitives"][p];
      draco::Mesh mesh;
      mesh.set_num_points(static_cast<std::uint32_t>(prim.positions.size()));
      std::vector<std::uint32_t> indices = prim.indices;  // Fox has none: a triangle soup
      if (indices.empty()) {
        for (std::uint32_t i = 0; i < prim.positions.size(); ++i) indices.push_back(i);
      }
      for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        draco::Mesh::Face face;
        for (int k = 0; k < 3; ++k) face[k] = draco::PointIndex(indices[t + std::size_t(k)]);
        mesh.AddFace(face);
      }
      json ids;
      ids["POSITION"] = AddDracoAttribute<glm::vec3, 3>(&mesh, draco::GeometryAttribute::POSITION,
                                                        draco::DT_FLOAT32, prim.positions);
      if (!prim.normals.empty()) {
        std::vector<glm::vec3> n = prim.normals;
        for (glm::vec3& v : n) v = glm::normalize(v);
        ids["NORMAL"] = AddDracoAttribute<glm::vec3, 3>(&mesh, draco::GeometryAttribute::NORMAL,
                                                        draco::DT_FLOAT32, n);
      }
      if (!prim.texcoords.empty()) {
        ids["TEXCOORD_0"] = AddDracoAttribute<glm::vec2, 2>(
            &mesh, draco::GeometryAttribute::TEX_COORD, draco::DT_FLOAT32, prim.texcoords[0]);
      }
      if (!prim.joints.empty()) {
        REQUIRE(prim.joints.size() == 1);  // the shared characters have 4 influences at most
        // The exported (renormalised) weights, read back from the plain export.
        const std::size_t acc = out["attributes"]["WEIGHTS_0"].get<std::size_t>();
        const json& a = doc["accessors"][acc];
        const json& view = doc["bufferViews"][a["bufferView"].get<std::size_t>()];
        std::vector<glm::vec4> w(prim.positions.size());
        std::memcpy(w.data(), bin.data() + view.value("byteOffset", std::size_t{0}),
                    w.size() * sizeof(glm::vec4));
        ids["JOINTS_0"] = AddDracoAttribute<glm::u16vec4, 4>(
            &mesh, draco::GeometryAttribute::GENERIC, draco::DT_UINT16, prim.joints[0]);
        ids["WEIGHTS_0"] = AddDracoAttribute<glm::vec4, 4>(&mesh, draco::GeometryAttribute::GENERIC,
                                                           draco::DT_FLOAT32, w);
      }
      draco::Encoder encoder;
      encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
      encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
      encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, 12);
      encoder.SetAttributeQuantization(draco::GeometryAttribute::GENERIC, 12);
      draco::EncoderBuffer buffer;
      const draco::Status encoded = encoder.EncodeMeshToBuffer(mesh, &buffer);
      INFO(encoded.error_msg_string());
      REQUIRE(encoded.ok());
      while (bin.size() % 4 != 0) bin.push_back('\0');
      doc["bufferViews"].push_back(
          {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", buffer.size()}});
      bin.append(buffer.data(), buffer.size());
      out["extensions"]["KHR_draco_mesh_compression"] = {
          {"bufferView", doc["bufferViews"].size() - 1}, {"attributes", ids}};
      // The accessors keep type, count and bounds; their data is now Draco's.
      for (auto it = ids.begin(); it != ids.end(); ++it) {
        json& a = doc["accessors"][out["attributes"][it.key()].get<std::size_t>()];
        a.erase("bufferView");
        a.erase("byteOffset");
      }
      if (out.contains("indices")) {
        json& a = doc["accessors"][out["indices"].get<std::size_t>()];
        a.erase("bufferView");
        a.erase("byteOffset");
      }
    }
  }
  while (bin.size() % 4 != 0) bin.push_back('\0');
  doc["buffers"][0]["byteLength"] = bin.size();
  for (const char* list : {"extensionsUsed", "extensionsRequired"}) {
    doc[list].push_back("KHR_draco_mesh_compression");
  }
  std::string text = doc.dump();
  while (text.size() % 4 != 0) text.push_back(' ');
  std::string out;
  PutU32(&out, 0x46546C67);
  PutU32(&out, 2);
  PutU32(&out, static_cast<std::uint32_t>(28 + text.size() + bin.size()));
  PutU32(&out, static_cast<std::uint32_t>(text.size()));
  PutU32(&out, 0x4E4F534A);
  out += text;
  PutU32(&out, static_cast<std::uint32_t>(bin.size()));
  PutU32(&out, 0x004E4942);
  out += bin;
  return out;
}

void WriteBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

/// The largest distance from a vertex of `a`'s rest pose to the nearest vertex of `b`'s (Draco
/// reorders and may merge points).
double NearestVertexDistance(const Asset& a, const Asset& b, double* diagonal) {
  std::vector<glm::dvec3> pa, pb;
  for (const auto& [key, v] : Draw(a, -1, 0.0)) pa.insert(pa.end(), v.begin(), v.end());
  for (const auto& [key, v] : Draw(b, -1, 0.0)) pb.insert(pb.end(), v.begin(), v.end());
  glm::dvec3 lo(1e300), hi(-1e300);
  double worst = 0.0;
  for (const glm::dvec3& p : pa) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
    double best = 1e300;
    for (const glm::dvec3& q : pb) best = std::min(best, glm::distance(p, q));
    worst = std::max(worst, best);
  }
  *diagonal = glm::distance(lo, hi);
  return worst;
}

TEST_CASE("Draco-compressed shared characters import like the originals",
          "[gltf][compression][draco][data]") {
  if (!fs::exists(kSharedGltfDir)) {
    WARN("skipped: ../shared/data is absent");
    return;
  }
  TempDir tmp;
  for (const char* name : kCharacters) {
    INFO(name);
    Asset asset;
    REQUIRE(ImportGltf(std::string(kSharedGltfDir) + name, &asset).ok());
    const std::string file = tmp.File("draco.glb");
    WriteBytes(file, WriteDracoGlb(asset));
    Asset back;
    const Status s = ImportGltf(file, &back);
    INFO(s.message());
    REQUIRE(s.ok());
    CheckSameSceneCounts(asset, back);
    double diagonal = 0.0;
    const double d = NearestVertexDistance(asset, back, &diagonal);
    std::printf(
        "%-18s Draco 14-bit positions: nearest-vertex distance %.3g (%.2g of the "
        "diagonal)\n",
        name, d, d / diagonal);
    // 14 bits over the position box: half a step per axis, about 5e-5 of the diagonal.
    CHECK(d <= 1e-4 * diagonal);
  }
}

TEST_CASE("Corrupt meshopt and Draco data fail with the file and the JSON pointer",
          "[gltf][compression]") {
  if (!fs::exists(kSharedGltfDir)) {
    WARN("skipped: ../shared/data is absent");
    return;
  }
  TempDir tmp;
  Asset asset;
  REQUIRE(ImportGltf(std::string(kSharedGltfDir) + "RiggedSimple.glb", &asset).ok());
  GltfExportOptions options;
  options.quantize = options.compress = true;
  std::string bytes;
  REQUIRE(SerializeGltf(asset, options, true, &bytes).ok());
  // Zero the BIN chunk: every encoded stream becomes garbage.
  const std::size_t bin = 20 + U32(bytes, 12) + 8;
  std::string broken = bytes;
  std::fill(broken.begin() + static_cast<std::ptrdiff_t>(bin), broken.end(), '\0');
  const std::string file = tmp.File("broken.glb");
  WriteBytes(file, broken);
  Asset back;
  Status s = ImportGltf(file, &back);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find(file) != std::string::npos);
  CHECK(s.message().find("/extensions/EXT_meshopt_compression") != std::string::npos);

  std::string draco = WriteDracoGlb(asset);
  const std::size_t dbin = 20 + U32(draco, 12) + 8;
  const json doc = json::parse(draco.substr(20, U32(draco, 12)));
  const json& view = doc["bufferViews"][doc["meshes"][0]["primitives"][0]["extensions"]
                                           ["KHR_draco_mesh_compression"]["bufferView"]
                                               .get<std::size_t>()];
  const std::size_t at = dbin + view["byteOffset"].get<std::size_t>();
  std::fill(draco.begin() + static_cast<std::ptrdiff_t>(at),
            draco.begin() + static_cast<std::ptrdiff_t>(at + view["byteLength"].get<std::size_t>()),
            '\x55');
  WriteBytes(file, draco);
  s = ImportGltf(file, &back);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("/extensions/KHR_draco_mesh_compression") != std::string::npos);
}

TEST_CASE("A gltfpack-style meshopt file and a Draco file of CesiumMan fit like the original",
          "[gltf][compression][fit][data][heavy]") {
  const std::string source = std::string(kSharedGltfDir) + "CesiumMan.glb";
  if (!fs::exists(source)) {
    WARN("skipped: " << source << " is absent (../shared/data)");
    return;
  }
  TempDir tmp;
  Asset asset;
  REQUIRE(ImportGltf(source, &asset).ok());
  GltfExportOptions packed;
  packed.quantize = packed.compress = true;
  GltfExportReport report;
  REQUIRE(ExportGltf(asset, packed, tmp.File("meshopt.glb"), &report).ok());
  WriteBytes(tmp.File("draco.glb"), WriteDracoGlb(asset));

  CharacterFitOptions options;
  options.fit.threads = 2;
  // A quantised file's mesh space is its position grid (the dequantising scale is in the
  // inverse bind matrices), so the fit errors compare relative to the mesh-space diagonal.
  auto fit = [&](const std::string& file, CharacterFitReport* out) {
    Asset a;
    Status s = ImportGltf(file, &a);
    INFO(file << ": " << s.message());
    REQUIRE(s.ok());
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const AssetMesh& m : a.meshes) {
      for (const AssetPrimitive& p : m.primitives) {
        for (const glm::vec3& v : p.positions) {
          lo = glm::min(lo, glm::dvec3(v));
          hi = glm::max(hi, glm::dvec3(v));
        }
      }
    }
    Character ch;
    s = FitCharacter(a, options, &ch, out);
    INFO(s.message());
    REQUIRE(s.ok());
    out->e1_mean /= glm::distance(lo, hi);
    out->e1_max /= glm::distance(lo, hi);
  };
  CharacterFitReport original, meshopt, draco;
  fit(source, &original);
  fit(tmp.File("meshopt.glb"), &meshopt);
  fit(tmp.File("draco.glb"), &draco);
  std::printf(
      "CesiumMan fit E1 mean/max: original %.4g/%.4g, meshopt+quantized %.4g/%.4g, "
      "Draco %.4g/%.4g (of the mesh-space diagonal)\n",
      original.e1_mean, original.e1_max, meshopt.e1_mean, meshopt.e1_max, draco.e1_mean,
      draco.e1_max);
  // The same parts, every vertex bound, and the fit error close to the original's: the inputs
  // differ by their quantisation (meshopt file: a 15/16-bit grid, about 2e-5 of the diagonal;
  // Draco: 14 bits), which is a third of E1 mean, so E1 mean may grow by some 15 % (measured:
  // CesiumMan +4 % meshopt, -5 % Draco, on the same control mesh). The quantised input may
  // also tip the part between the control meshes with and without creases, whose Hausdorff
  // distances are close on CesiumMan (docs/characters.md, "Creases or not"; measured: the
  // original keeps the one without creases, E1 mean 8.3e-5 of the diagonal, the meshopt and
  // Draco files the crease-aware one, 2.5e-5 and 2.4e-5): a compressed input must not fit
  // worse. E1 max is one vertex on a crease: it stays a small fraction of the diagonal,
  // held under 0.2 %.
  for (const CharacterFitReport* r : {&meshopt, &draco}) {
    CHECK(r->parts_fitted == original.parts_fitted);
    CHECK(r->vertices_bound == r->vertices);
    CHECK(r->e1_mean <= 1.2 * original.e1_mean);
    CHECK(r->e1_max <= 2e-3);
  }
  CHECK(meshopt.vertices == original.vertices);
}

}  // namespace
}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// glTF 2.0 export of the neutral asset module with tinygltf 2.7.
//
// tinygltf only serialises what it is given, so every rule of the Khronos validator is ours:
// one buffer with one 4-byte aligned bufferView per accessor, exact float32 min/max for
// POSITION (and morph POSITION) and animation inputs, unit normals/tangents/rotation keys,
// skin weights renormalised in float32 as the validator sums them (residue into the largest
// weight, joint 0 padding), inverse bind matrices with an exact last row, and images passed
// through as the bytes of a bufferView (tinygltf would otherwise decode and re-encode them).
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "dermis/asset/asset_validate.h"
#include "dermis/core/file_io.h"
#include "dermis/core/path.h"
#include "dermis/plugins/gltf.h"
#include "gltf_meshopt_encode.h"
#include "gltf_quantize.h"

namespace dermis {
namespace {

constexpr int kArrayBuffer = TINYGLTF_TARGET_ARRAY_BUFFER;
constexpr int kElementArrayBuffer = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;
constexpr int kNoTarget = 0;

/// Mantissa bits of the EXPONENTIAL filter for the float morph normals of a quantised and
/// compressed export: a relative error of 2^-15 of the largest component of the delta.
constexpr int kExponentialFilterBits = 16;

/// Tolerance on the last row of an inverse bind matrix before it is forced to (0, 0, 0, 1).
constexpr float kIbmLastRowTolerance = 1e-6f;

std::string Pointer(const char* array, std::size_t index) {
  return std::string("/") + array + "/" + std::to_string(index);
}

/// Builds the tinygltf model and its single binary buffer.
class ModelBuilder {
 public:
  ModelBuilder(const Asset& asset, const GltfExportOptions& options, GltfExportReport* report)
      : asset_(asset), options_(options), report_(*report) {}

  Status Build();
  tinygltf::Model& model() { return model_; }

 private:
  Status Fail(const std::string& pointer, const std::string& message) const {
    return Status::InvalidInput(Source() + ": " + pointer + ": " + message);
  }
  std::string Source() const { return asset_.source.empty() ? "<asset>" : asset_.source; }

  /// Appends `size` bytes at a 4-byte aligned offset as a new bufferView.
  int AddView(const void* data, std::size_t size, int target);
  /// A tightly packed accessor of `count` elements of `components` floats.
  int AddFloatAccessor(const std::vector<float>& values, int type, int components, int target,
                       bool bounds);
  int AddAccessor(int view, int component_type, int type, std::size_t count);
  /// KHR_mesh_quantization accessors (docs/gltf-compression.md): positions on the grid, morph
  /// position deltas in grid steps, signed / unsigned normalised shorts. Element data is padded
  /// to 4 bytes (VEC3 of shorts: byteStride 8).
  int AddGridPositions(const std::vector<glm::vec3>& positions);
  int AddGridDeltas(const std::vector<glm::vec3>& base, const std::vector<glm::vec3>& deltas);
  int AddNormalized16(const std::vector<float>& values, int components, bool is_signed,
                      bool bounds);
  /// Normals (unit, or morph deltas) as snorm16 if every value is in [-1, 1], else float32.
  int AddUnitOrDelta(const std::vector<float>& values, bool unit);

  Status AddMaterials();
  void AddTexturesAndImages(Status* status);
  void AddNodesAndScenes();
  /// The matrix taking grid coordinates to model positions (uniform scale, then translation).
  glm::dmat4 Dequantization() const;
  Status AddMeshes();
  Status AddPrimitive(std::size_t mesh_index, std::size_t primitive_index,
                      tinygltf::Primitive* out);
  Status AddSkinAttributes(const AssetPrimitive& primitive, const std::string& pointer,
                           tinygltf::Primitive* out);
  Status AddSkins();
  Status AddAnimations();

  const Asset& asset_;
  const GltfExportOptions& options_;
  GltfExportReport& report_;
  gltf_quantize::PositionGrid grid_;
  tinygltf::Model model_;
  std::vector<unsigned char> bin_;
  std::set<std::string> extensions_used_;
  bool joints_u8_ = true;
  /// With quantize: the node that now holds the mesh (and morph weights) of node i, or -1.
  std::vector<int> mesh_child_;
};

int ModelBuilder::AddView(const void* data, std::size_t size, int target) {
  while (bin_.size() % 4 != 0) bin_.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = bin_.size();
  view.byteLength = size;
  view.target = target;
  const auto* bytes = static_cast<const unsigned char*>(data);
  bin_.insert(bin_.end(), bytes, bytes + size);
  model_.bufferViews.push_back(std::move(view));
  return static_cast<int>(model_.bufferViews.size() - 1);
}

int ModelBuilder::AddGridPositions(const std::vector<glm::vec3>& positions) {
  const std::size_t n = positions.size();
  std::vector<std::uint16_t> data(4 * n, 0);
  std::uint16_t lo[3] = {65535, 65535, 65535}, hi[3] = {0, 0, 0};
  for (std::size_t i = 0; i < n; ++i) {
    const glm::u16vec3 q = gltf_quantize::Quantize(grid_, positions[i]);
    for (int c = 0; c < 3; ++c) {
      data[4 * i + static_cast<std::size_t>(c)] = q[c];
      lo[c] = std::min(lo[c], q[c]);
      hi[c] = std::max(hi[c], q[c]);
    }
    const double error =
        glm::distance(gltf_quantize::Dequantize(grid_, glm::ivec3(q)), glm::dvec3(positions[i]));
    report_.max_position_error = std::max(report_.max_position_error, error);
  }
  const int view = AddView(data.data(), data.size() * sizeof(std::uint16_t), kArrayBuffer);
  model_.bufferViews[static_cast<std::size_t>(view)].byteStride = 8;
  const int index =
      AddAccessor(view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC3, n);
  tinygltf::Accessor& accessor = model_.accessors[static_cast<std::size_t>(index)];
  accessor.minValues = {static_cast<double>(lo[0]), static_cast<double>(lo[1]),
                        static_cast<double>(lo[2])};
  accessor.maxValues = {static_cast<double>(hi[0]), static_cast<double>(hi[1]),
                        static_cast<double>(hi[2])};
  return index;
}

int ModelBuilder::AddGridDeltas(const std::vector<glm::vec3>& base,
                                const std::vector<glm::vec3>& deltas) {
  // The delta of the grid coordinates of the morphed and the base position: the morphed
  // position is then rounded to the grid exactly as a base position is.
  const std::size_t n = deltas.size();
  std::vector<std::int16_t> data(4 * n, 0);
  int lo[3] = {32767, 32767, 32767}, hi[3] = {-32767, -32767, -32767};
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3 morphed = base[i] + deltas[i];
    const glm::ivec3 qb(gltf_quantize::Quantize(grid_, base[i]));
    const glm::ivec3 qm(gltf_quantize::Quantize(grid_, morphed));
    for (int c = 0; c < 3; ++c) {
      const int d = qm[c] - qb[c];  // |d| <= 2^15 - 1: the grid has at most 15 bits here
      data[4 * i + static_cast<std::size_t>(c)] = static_cast<std::int16_t>(d);
      lo[c] = std::min(lo[c], d);
      hi[c] = std::max(hi[c], d);
    }
    const double error = glm::distance(gltf_quantize::Dequantize(grid_, qm), glm::dvec3(morphed));
    report_.max_position_error = std::max(report_.max_position_error, error);
  }
  const int view = AddView(data.data(), data.size() * sizeof(std::int16_t), kArrayBuffer);
  model_.bufferViews[static_cast<std::size_t>(view)].byteStride = 8;
  const int index = AddAccessor(view, TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_TYPE_VEC3, n);
  if (n > 0) {
    tinygltf::Accessor& accessor = model_.accessors[static_cast<std::size_t>(index)];
    accessor.minValues = {static_cast<double>(lo[0]), static_cast<double>(lo[1]),
                          static_cast<double>(lo[2])};
    accessor.maxValues = {static_cast<double>(hi[0]), static_cast<double>(hi[1]),
                          static_cast<double>(hi[2])};
  }
  return index;
}

int ModelBuilder::AddNormalized16(const std::vector<float>& values, int components, bool is_signed,
                                  bool bounds) {
  const std::size_t c = static_cast<std::size_t>(components);
  const std::size_t n = values.size() / c;
  const std::size_t padded = (c * 2 + 3) / 4 * 2;  // shorts per element, 4-byte aligned
  std::vector<std::uint16_t> data(padded * n, 0);
  std::vector<double> lo(c, 65535.0), hi(c, -65535.0);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = 0; k < c; ++k) {
      const float v = values[i * c + k];
      double decoded;
      if (is_signed) {
        const std::int16_t q = gltf_quantize::Snorm16(v);
        std::memcpy(&data[i * padded + k], &q, sizeof q);
        decoded = std::max(q / 32767.0, -1.0);
      } else {
        const std::uint16_t q = gltf_quantize::Unorm16(v);
        data[i * padded + k] = q;
        decoded = q / 65535.0;
      }
      lo[k] = std::min(lo[k], decoded);
      hi[k] = std::max(hi[k], decoded);
    }
  }
  const int view = AddView(data.data(), data.size() * sizeof(std::uint16_t), kArrayBuffer);
  if (padded != c) {
    model_.bufferViews[static_cast<std::size_t>(view)].byteStride =
        static_cast<int>(padded * sizeof(std::uint16_t));
  }
  const int type = c == 2 ? TINYGLTF_TYPE_VEC2 : c == 3 ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC4;
  const int index = AddAccessor(
      view, is_signed ? TINYGLTF_COMPONENT_TYPE_SHORT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
      type, n);
  tinygltf::Accessor& accessor = model_.accessors[static_cast<std::size_t>(index)];
  accessor.normalized = true;
  if (bounds && n > 0) {
    accessor.minValues = lo;
    accessor.maxValues = hi;
  }
  return index;
}

int ModelBuilder::AddUnitOrDelta(const std::vector<float>& values, bool unit) {
  bool in_range = true;
  for (const float v : values) in_range = in_range && v >= -1.0f && v <= 1.0f;
  if (!in_range) {
    ++report_.float_target_accessors;
    return AddFloatAccessor(values, TINYGLTF_TYPE_VEC3, 3, kArrayBuffer, false);
  }
  const int index = AddNormalized16(values, 3, /*is_signed=*/true, false);
  if (unit) {
    for (std::size_t i = 0; i + 2 < values.size(); i += 3) {
      glm::dvec3 q;
      for (int c = 0; c < 3; ++c) {
        q[c] = std::max(gltf_quantize::Snorm16(values[i + static_cast<std::size_t>(c)]) / 32767.0,
                        -1.0);
      }
      const glm::dvec3 v(values[i], values[i + 1], values[i + 2]);
      const double cosine = glm::dot(glm::normalize(q), glm::normalize(v));
      const double degrees = std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / 3.14159265358979;
      report_.max_normal_error_degrees = std::max(report_.max_normal_error_degrees, degrees);
    }
  }
  return index;
}

int ModelBuilder::AddAccessor(int view, int component_type, int type, std::size_t count) {
  tinygltf::Accessor accessor;
  accessor.bufferView = view;
  accessor.byteOffset = 0;
  accessor.componentType = component_type;
  accessor.type = type;
  accessor.count = count;
  model_.accessors.push_back(std::move(accessor));
  return static_cast<int>(model_.accessors.size() - 1);
}

int ModelBuilder::AddFloatAccessor(const std::vector<float>& values, int type, int components,
                                   int target, bool bounds) {
  const std::size_t n = static_cast<std::size_t>(components);
  const std::size_t count = values.size() / n;
  const int view = AddView(values.data(), values.size() * sizeof(float), target);
  const int index = AddAccessor(view, TINYGLTF_COMPONENT_TYPE_FLOAT, type, count);
  if (bounds && count > 0) {
    // Exact bounds of the float32 data written: float -> double is exact and the JSON writer
    // prints doubles so that they read back identically.
    std::vector<float> lo(values.begin(), values.begin() + components);
    std::vector<float> hi = lo;
    for (std::size_t i = 0; i < count; ++i) {
      for (std::size_t c = 0; c < n; ++c) {
        lo[c] = std::min(lo[c], values[i * n + c]);
        hi[c] = std::max(hi[c], values[i * n + c]);
      }
    }
    tinygltf::Accessor& accessor = model_.accessors[static_cast<std::size_t>(index)];
    accessor.minValues.assign(lo.begin(), lo.end());
    accessor.maxValues.assign(hi.begin(), hi.end());
  }
  return index;
}

std::vector<float> Flatten(const std::vector<glm::vec3>& v) {
  std::vector<float> out;
  out.reserve(v.size() * 3);
  for (const glm::vec3& p : v) out.insert(out.end(), {p.x, p.y, p.z});
  return out;
}

std::vector<float> Flatten(const std::vector<glm::vec2>& v) {
  std::vector<float> out;
  out.reserve(v.size() * 2);
  for (const glm::vec2& p : v) out.insert(out.end(), {p.x, p.y});
  return out;
}

std::vector<float> Flatten(const std::vector<glm::vec4>& v) {
  std::vector<float> out;
  out.reserve(v.size() * 4);
  for (const glm::vec4& p : v) out.insert(out.end(), {p.x, p.y, p.z, p.w});
  return out;
}

/// Scales (x, y, z) to unit length in float; returns false (leaving it) if it is zero.
bool NormalizeInFloat(float* x, float* y, float* z) {
  const double len = std::sqrt(static_cast<double>(*x) * *x + static_cast<double>(*y) * *y +
                               static_cast<double>(*z) * *z);
  if (!(len > 0.0) || !std::isfinite(len)) return false;
  *x = static_cast<float>(*x / len);
  *y = static_cast<float>(*y / len);
  *z = static_cast<float>(*z / len);
  return true;
}

/// Collects every extension name used inside a JSON value (keys of any "extensions" object).
void CollectExtensions(const nlohmann::json& value, std::set<std::string>* names) {
  if (value.is_object()) {
    for (auto it = value.begin(); it != value.end(); ++it) {
      if (it.key() == "extensions" && it.value().is_object()) {
        for (auto ext = it.value().begin(); ext != it.value().end(); ++ext) {
          names->insert(ext.key());
        }
      }
      CollectExtensions(it.value(), names);
    }
  } else if (value.is_array()) {
    for (const nlohmann::json& item : value) CollectExtensions(item, names);
  }
}

Status ModelBuilder::AddMaterials() {
  tinygltf::TinyGLTF loader;
  for (std::size_t i = 0; i < asset_.materials.size(); ++i) {
    const AssetMaterial& material = asset_.materials[i];
    const std::string pointer = Pointer("materials", i);
    const nlohmann::json parsed = nlohmann::json::parse(material.json, nullptr, false);
    if (parsed.is_discarded() || !parsed.is_object()) {
      return Fail(pointer, "material json is not a JSON object");
    }
    CollectExtensions(parsed, &extensions_used_);
    // tinygltf parses a material only as part of a document: wrap it in a minimal one.
    nlohmann::json doc = {{"asset", {{"version", "2.0"}}}, {"materials", {parsed}}};
    const std::string text = doc.dump();
    tinygltf::Model parsed_model;
    std::string err, warn;
    if (!loader.LoadASCIIFromString(&parsed_model, &err, &warn, text.c_str(),
                                    static_cast<unsigned int>(text.size()), "") ||
        parsed_model.materials.size() != 1) {
      return Fail(pointer, "bad material: " + err);
    }
    tinygltf::Material out = std::move(parsed_model.materials[0]);
    if (!material.name.empty()) out.name = material.name;
    const int textures = static_cast<int>(asset_.textures.size());
    for (const int index :
         {out.pbrMetallicRoughness.baseColorTexture.index,
          out.pbrMetallicRoughness.metallicRoughnessTexture.index, out.normalTexture.index,
          out.occlusionTexture.index, out.emissiveTexture.index}) {
      if (index >= textures) {
        return Fail(pointer, "texture " + std::to_string(index) + " out of range (" +
                                 std::to_string(textures) + " textures)");
      }
    }
    model_.materials.push_back(std::move(out));
  }
  return Status::Ok();
}

std::string SniffMimeType(const std::string& bytes) {
  if (bytes.size() >= 8 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0) return "image/png";
  if (bytes.size() >= 3 && bytes.compare(0, 3, "\xff\xd8\xff") == 0) return "image/jpeg";
  if (bytes.size() >= 12 && bytes.compare(0, 4, "RIFF") == 0 && bytes.compare(8, 4, "WEBP") == 0) {
    return "image/webp";
  }
  return "";
}

void ModelBuilder::AddTexturesAndImages(Status* status) {
  for (const AssetSampler& s : asset_.samplers) {
    tinygltf::Sampler sampler;
    sampler.name = s.name;
    sampler.magFilter = s.mag_filter;
    sampler.minFilter = s.min_filter;
    sampler.wrapS = s.wrap_s;
    sampler.wrapT = s.wrap_t;
    model_.samplers.push_back(std::move(sampler));
  }
  for (std::size_t i = 0; i < asset_.images.size(); ++i) {
    const AssetImage& image = asset_.images[i];
    if (image.bytes.empty()) {
      *status = Fail(Pointer("images", i), "image has no bytes");
      return;
    }
    tinygltf::Image out;
    out.name = image.name;
    out.mimeType = image.mime_type.empty() ? SniffMimeType(image.bytes) : image.mime_type;
    if (out.mimeType.empty()) {
      *status = Fail(Pointer("images", i), "unknown image type (no mime type, not PNG/JPEG)");
      return;
    }
    // Bytes through a bufferView with an empty uri: tinygltf writes them untouched.
    out.bufferView = AddView(image.bytes.data(), image.bytes.size(), kNoTarget);
    out.as_is = true;
    model_.images.push_back(std::move(out));
  }
  for (const AssetTexture& t : asset_.textures) {
    tinygltf::Texture texture;
    texture.name = t.name;
    texture.source = t.image;
    texture.sampler = t.sampler;
    model_.textures.push_back(std::move(texture));
  }
}

void ModelBuilder::AddNodesAndScenes() {
  for (const AssetNode& n : asset_.nodes) {
    tinygltf::Node node;
    node.name = n.name;
    for (const Index child : n.children) node.children.push_back(static_cast<int>(child));
    if (n.has_matrix) {
      for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) node.matrix.push_back(n.matrix[c][r]);
      }
    } else {
      if (n.translation != glm::dvec3(0.0)) {
        node.translation = {n.translation.x, n.translation.y, n.translation.z};
      }
      if (n.rotation != glm::dquat(1.0, 0.0, 0.0, 0.0)) {
        const glm::dquat q = glm::normalize(n.rotation);
        node.rotation = {q.x, q.y, q.z, q.w};
      }
      if (n.scale != glm::dvec3(1.0)) node.scale = {n.scale.x, n.scale.y, n.scale.z};
    }
    node.mesh = static_cast<int>(n.mesh);
    node.skin = static_cast<int>(n.skin);
    node.weights = n.weights;
    model_.nodes.push_back(std::move(node));
  }
  for (const AssetScene& s : asset_.scenes) {
    tinygltf::Scene scene;
    scene.name = s.name;
    for (const Index node : s.nodes) scene.nodes.push_back(static_cast<int>(node));
    model_.scenes.push_back(std::move(scene));
  }
  model_.defaultScene = static_cast<int>(asset_.default_scene);
  if (!options_.quantize) return;
  // An unskinned mesh moves to a new child node whose matrix is the dequantising transform
  // (the node's own transform, animation and children stay as they were).
  const glm::dmat4 d = Dequantization();
  mesh_child_.assign(asset_.nodes.size(), -1);
  for (std::size_t i = 0; i < asset_.nodes.size(); ++i) {
    if (model_.nodes[i].mesh < 0 || model_.nodes[i].skin >= 0) continue;
    tinygltf::Node child;
    child.name = model_.nodes[i].name;
    child.mesh = model_.nodes[i].mesh;
    child.weights = std::move(model_.nodes[i].weights);
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) child.matrix.push_back(d[c][r]);
    }
    model_.nodes[i].mesh = -1;
    model_.nodes[i].weights.clear();
    mesh_child_[i] = static_cast<int>(model_.nodes.size());
    model_.nodes[i].children.push_back(mesh_child_[i]);
    model_.nodes.push_back(std::move(child));
  }
}

glm::dmat4 ModelBuilder::Dequantization() const {
  glm::dmat4 d(grid_.step);
  d[3] = glm::dvec4(grid_.origin, 1.0);
  return d;
}

Status ModelBuilder::AddMeshes() {
  // JOINTS as bytes when every skin (and every joint index) fits.
  for (const AssetSkin& skin : asset_.skins) {
    if (skin.joints.size() >= 256) joints_u8_ = false;
  }
  for (const AssetMesh& mesh : asset_.meshes) {
    for (const AssetPrimitive& primitive : mesh.primitives) {
      for (const auto& set : primitive.joints) {
        for (const glm::u16vec4& j : set) {
          if (std::max({j.x, j.y, j.z, j.w}) >= 256) joints_u8_ = false;
        }
      }
    }
  }
  for (std::size_t m = 0; m < asset_.meshes.size(); ++m) {
    const AssetMesh& mesh = asset_.meshes[m];
    tinygltf::Mesh out;
    out.name = mesh.name;
    out.weights.assign(mesh.weights.begin(), mesh.weights.end());
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      tinygltf::Primitive primitive;
      const Status status = AddPrimitive(m, p, &primitive);
      if (!status.ok()) return status;
      out.primitives.push_back(std::move(primitive));
    }
    model_.meshes.push_back(std::move(out));
  }
  return Status::Ok();
}

Status ModelBuilder::AddPrimitive(std::size_t mesh_index, std::size_t primitive_index,
                                  tinygltf::Primitive* out) {
  const AssetPrimitive& primitive = asset_.meshes[mesh_index].primitives[primitive_index];
  const std::string pointer =
      Pointer("meshes", mesh_index) + Pointer("primitives", primitive_index);
  const std::size_t n = primitive.positions.size();
  if (n == 0) return Fail(pointer, "primitive has no vertices");
  out->mode = static_cast<int>(primitive.mode);
  out->material = static_cast<int>(primitive.material);
  const bool q = options_.quantize;
  out->attributes["POSITION"] =
      q ? AddGridPositions(primitive.positions)
        : AddFloatAccessor(Flatten(primitive.positions), TINYGLTF_TYPE_VEC3, 3, kArrayBuffer,
                           /*bounds=*/true);
  if (!primitive.normals.empty()) {
    std::vector<float> normals = Flatten(primitive.normals);
    for (std::size_t i = 0; i < n; ++i) {
      float* v = &normals[3 * i];
      if (!NormalizeInFloat(v, v + 1, v + 2)) {  // a zero normal: any unit vector is valid
        v[0] = 0.0f;
        v[1] = 0.0f;
        v[2] = 1.0f;
      }
    }
    out->attributes["NORMAL"] =
        q ? AddUnitOrDelta(normals, /*unit=*/true)
          : AddFloatAccessor(normals, TINYGLTF_TYPE_VEC3, 3, kArrayBuffer, false);
  }
  if (!primitive.tangents.empty()) {
    std::vector<float> tangents = Flatten(primitive.tangents);
    for (std::size_t i = 0; i < n; ++i) {
      float* v = &tangents[4 * i];
      if (!NormalizeInFloat(v, v + 1, v + 2)) {
        v[0] = 1.0f;
        v[1] = 0.0f;
        v[2] = 0.0f;
      }
      v[3] = v[3] < 0.0f ? -1.0f : 1.0f;
    }
    out->attributes["TANGENT"] =
        q ? AddNormalized16(tangents, 4, /*is_signed=*/true, false)
          : AddFloatAccessor(tangents, TINYGLTF_TYPE_VEC4, 4, kArrayBuffer, false);
  }
  // Texture coordinates and colours in [0, 1] as normalised u16 (others stay float32: a
  // KHR_texture_transform remap would change the material).
  auto unit_range = [](const std::vector<float>& v) {
    return std::all_of(v.begin(), v.end(), [](float x) { return x >= 0.0f && x <= 1.0f; });
  };
  for (std::size_t s = 0; s < primitive.texcoords.size(); ++s) {
    const std::vector<float> uv = Flatten(primitive.texcoords[s]);
    if (q && unit_range(uv)) {
      for (const float x : uv) {
        const double e = std::fabs(gltf_quantize::Unorm16(x) / 65535.0 - static_cast<double>(x));
        report_.max_texcoord_error = std::max(report_.max_texcoord_error, e);
      }
      out->attributes["TEXCOORD_" + std::to_string(s)] =
          AddNormalized16(uv, 2, /*is_signed=*/false, false);
    } else {
      out->attributes["TEXCOORD_" + std::to_string(s)] =
          AddFloatAccessor(uv, TINYGLTF_TYPE_VEC2, 2, kArrayBuffer, false);
    }
  }
  for (std::size_t s = 0; s < primitive.colors.size(); ++s) {
    const std::vector<float> rgba = Flatten(primitive.colors[s]);
    out->attributes["COLOR_" + std::to_string(s)] =
        q && unit_range(rgba) ? AddNormalized16(rgba, 4, /*is_signed=*/false, false)
                              : AddFloatAccessor(rgba, TINYGLTF_TYPE_VEC4, 4, kArrayBuffer, false);
  }
  const Status skin_status = AddSkinAttributes(primitive, pointer, out);
  if (!skin_status.ok()) return skin_status;

  if (!primitive.indices.empty()) {
    const std::uint32_t max_index =
        *std::max_element(primitive.indices.begin(), primitive.indices.end());
    // 65535 is the primitive restart value of u16 indices: it needs u32.
    if (max_index < 65535u) {
      std::vector<std::uint16_t> small(primitive.indices.begin(), primitive.indices.end());
      const int view =
          AddView(small.data(), small.size() * sizeof(std::uint16_t), kElementArrayBuffer);
      out->indices = AddAccessor(view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR,
                                 small.size());
    } else {
      const int view =
          AddView(primitive.indices.data(), primitive.indices.size() * sizeof(std::uint32_t),
                  kElementArrayBuffer);
      out->indices = AddAccessor(view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                                 primitive.indices.size());
    }
  }

  for (const AssetMorphTarget& target : primitive.targets) {
    std::map<std::string, int> attributes;
    if (!target.positions.empty()) {
      attributes["POSITION"] =
          q && target.positions.size() == n
              ? AddGridDeltas(primitive.positions, target.positions)
              : AddFloatAccessor(Flatten(target.positions), TINYGLTF_TYPE_VEC3, 3, kArrayBuffer,
                                 /*bounds=*/true);
    }
    if (!target.normals.empty()) {
      attributes["NORMAL"] =
          q ? AddUnitOrDelta(Flatten(target.normals), /*unit=*/false)
            : AddFloatAccessor(Flatten(target.normals), TINYGLTF_TYPE_VEC3, 3, kArrayBuffer, false);
    }
    if (!target.tangents.empty()) {
      attributes["TANGENT"] = q ? AddUnitOrDelta(Flatten(target.tangents), /*unit=*/false)
                                : AddFloatAccessor(Flatten(target.tangents), TINYGLTF_TYPE_VEC3, 3,
                                                   kArrayBuffer, false);
    }
    out->targets.push_back(std::move(attributes));
  }
  return Status::Ok();
}

/// One vertex's influences: merged, filtered, truncated and renormalised in float32.
struct Influence {
  std::uint32_t joint;
  double weight;
};

/// The float32 sum of the non-zero weights in the validator's order (component-major over
/// the sets: slot c of set 0, slot c of set 1, ..., then slot c + 1).
float ValidatorSum(const std::vector<float>& slots, std::size_t sets) {
  float sum = 0.0f;
  for (std::size_t c = 0; c < 4; ++c) {
    for (std::size_t s = 0; s < sets; ++s) {
      const float w = slots[4 * s + c];
      if (w != 0.0f) sum = sum + w;
    }
  }
  return sum;
}

Status ModelBuilder::AddSkinAttributes(const AssetPrimitive& primitive, const std::string& pointer,
                                       tinygltf::Primitive* out) {
  if (primitive.joints.empty() && primitive.weights.empty()) return Status::Ok();
  if (primitive.joints.size() != primitive.weights.size()) {
    return Fail(pointer, "JOINTS and WEIGHTS set counts differ");
  }
  if (options_.max_influences < 1) {
    return Status::InvalidInput(Source() + ": max_influences must be >= 1 (got " +
                                std::to_string(options_.max_influences) + ")");
  }
  const std::size_t n = primitive.positions.size();
  const std::size_t max_influences = static_cast<std::size_t>(options_.max_influences);

  // Per vertex: all (joint, weight) pairs of every set, duplicates merged, zeros dropped,
  // the largest `max_influences` kept (ties: smaller joint first).
  std::vector<std::vector<Influence>> kept(n);
  std::size_t widest = 1;
  std::vector<Influence> all;
  for (std::size_t v = 0; v < n; ++v) {
    all.clear();
    for (std::size_t s = 0; s < primitive.joints.size(); ++s) {
      const glm::u16vec4 j = primitive.joints[s][v];
      const glm::vec4 w = primitive.weights[s][v];
      for (int c = 0; c < 4; ++c) {
        if (!(w[c] > 0.0f)) continue;
        auto it = std::find_if(all.begin(), all.end(),
                               [&](const Influence& x) { return x.joint == j[c]; });
        if (it == all.end()) {
          all.push_back({j[c], static_cast<double>(w[c])});
        } else {
          it->weight += static_cast<double>(w[c]);
        }
      }
    }
    std::sort(all.begin(), all.end(), [](const Influence& a, const Influence& b) {
      return a.weight != b.weight ? a.weight > b.weight : a.joint < b.joint;
    });
    if (all.size() > max_influences) all.resize(max_influences);
    if (all.empty()) all.push_back({0, 1.0});  // glTF needs weights summing to 1: joint 0
    widest = std::max(widest, all.size());
    kept[v] = all;
  }

  const std::size_t sets = (widest + 3) / 4;
  std::vector<std::vector<std::uint16_t>> joints(sets, std::vector<std::uint16_t>(4 * n, 0));
  std::vector<std::vector<float>> weights(sets, std::vector<float>(4 * n, 0.0f));
  std::vector<float> slots(4 * sets);
  std::vector<std::uint16_t> qslots(4 * sets);
  std::vector<std::vector<std::uint16_t>> quantized_weights;
  if (options_.quantize) {
    quantized_weights.assign(sets, std::vector<std::uint16_t>(4 * n, 0));
  }
  for (std::size_t v = 0; v < n; ++v) {
    const std::vector<Influence>& inf = kept[v];
    double total = 0.0;
    for (const Influence& x : inf) total += x.weight;
    // Slot k of the vertex is set k / 4, component k % 4; slot 0 holds the largest weight.
    std::fill(slots.begin(), slots.end(), 0.0f);
    for (std::size_t k = 0; k < inf.size(); ++k) {
      slots[k] = static_cast<float>(inf[k].weight / total);
    }
    // Push the float32 rounding residue into the largest weight until the validator's sum is
    // 1 (it converges in one or two steps; the check below guards the rest).
    for (int iteration = 0; iteration < 16; ++iteration) {
      const float sum = ValidatorSum(slots, sets);
      if (sum == 1.0f) break;
      slots[0] = slots[0] + (1.0f - sum);
    }
    std::size_t nonzero = 0;
    for (const float w : slots) nonzero += w != 0.0f ? 1 : 0;
    const float sum = ValidatorSum(slots, sets);
    if (std::fabs(static_cast<double>(sum) - 1.0) > 1e-7 * static_cast<double>(nonzero)) {
      return Status::Internal(Source() + ": " + pointer + ": weights of vertex " +
                              std::to_string(v) + " cannot be normalised in float32");
    }
    if (options_.quantize) {
      // Normalised u16 summing to exactly 65535; a weight rounded to 0 pads with joint 0.
      gltf_quantize::QuantizeWeights(slots.data(), slots.size(), qslots.data());
      for (std::size_t k = 0; k < slots.size(); ++k) {
        const double e = std::fabs(qslots[k] / 65535.0 - static_cast<double>(slots[k]));
        report_.max_weight_error = std::max(report_.max_weight_error, e);
        quantized_weights[k / 4][4 * v + k % 4] = qslots[k];
        if (k < inf.size() && qslots[k] != 0) {
          joints[k / 4][4 * v + k % 4] = static_cast<std::uint16_t>(inf[k].joint);
        }
      }
      continue;
    }
    for (std::size_t k = 0; k < inf.size(); ++k) {
      if (slots[k] == 0.0f) continue;  // underflowed: pad with joint 0 instead
      joints[k / 4][4 * v + k % 4] = static_cast<std::uint16_t>(inf[k].joint);
      weights[k / 4][4 * v + k % 4] = slots[k];
    }
  }

  for (std::size_t s = 0; s < sets; ++s) {
    int view;
    if (joints_u8_) {
      std::vector<std::uint8_t> bytes(joints[s].begin(), joints[s].end());
      view = AddView(bytes.data(), bytes.size(), kArrayBuffer);
    } else {
      view = AddView(joints[s].data(), joints[s].size() * sizeof(std::uint16_t), kArrayBuffer);
    }
    out->attributes["JOINTS_" + std::to_string(s)] = AddAccessor(
        view,
        joints_u8_ ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE : TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
        TINYGLTF_TYPE_VEC4, n);
    if (options_.quantize) {
      std::vector<std::uint16_t> q(4 * n);
      for (std::size_t i = 0; i < 4 * n; ++i) q[i] = quantized_weights[s][i];
      const int wview = AddView(q.data(), q.size() * sizeof(std::uint16_t), kArrayBuffer);
      const int index =
          AddAccessor(wview, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC4, n);
      model_.accessors[static_cast<std::size_t>(index)].normalized = true;
      out->attributes["WEIGHTS_" + std::to_string(s)] = index;
    } else {
      out->attributes["WEIGHTS_" + std::to_string(s)] =
          AddFloatAccessor(weights[s], TINYGLTF_TYPE_VEC4, 4, kArrayBuffer, false);
    }
  }
  return Status::Ok();
}

Status ModelBuilder::AddSkins() {
  // With quantize, the skins of skinned mesh nodes take the dequantising transform into their
  // inverse bind matrices: joint * IBM * D * q = joint * IBM * p (the skinned mesh's node
  // transform is ignored by glTF, so it cannot hold it).
  std::vector<bool> dequantize(asset_.skins.size(), false);
  if (options_.quantize) {
    for (const AssetNode& n : asset_.nodes) {
      if (n.mesh >= 0 && n.skin >= 0 && static_cast<std::size_t>(n.skin) < dequantize.size()) {
        dequantize[static_cast<std::size_t>(n.skin)] = true;
      }
    }
  }
  const glm::dmat4 d = Dequantization();
  for (std::size_t i = 0; i < asset_.skins.size(); ++i) {
    const AssetSkin& skin = asset_.skins[i];
    if (dequantize[i] && skin.has_inverse_bind_matrices &&
        skin.inverse_bind_matrices.size() != skin.joints.size()) {
      return Fail(Pointer("skins", i), "inverse bind matrix count differs from joint count");
    }
    if (dequantize[i]) {
      std::vector<float> values;
      values.reserve(16 * skin.joints.size());
      for (std::size_t j = 0; j < skin.joints.size(); ++j) {
        const glm::dmat4 ibm = skin.has_inverse_bind_matrices
                                   ? glm::dmat4(skin.inverse_bind_matrices[j])
                                   : glm::dmat4(1.0);
        const glm::dmat4 m = ibm * d;
        for (int c = 0; c < 4; ++c) {
          const double expected = c == 3 ? 1.0 : 0.0;
          if (!(std::fabs(m[c][3] - expected) <= kIbmLastRowTolerance)) {
            return Fail(Pointer("skins", i) + "/inverseBindMatrices/" + std::to_string(j),
                        "last row is not (0, 0, 0, 1)");
          }
          values.insert(values.end(), {static_cast<float>(m[c][0]), static_cast<float>(m[c][1]),
                                       static_cast<float>(m[c][2]), static_cast<float>(expected)});
        }
      }
      tinygltf::Skin out;
      out.name = skin.name;
      for (const Index joint : skin.joints) out.joints.push_back(static_cast<int>(joint));
      out.skeleton = static_cast<int>(skin.skeleton);
      out.inverseBindMatrices = AddFloatAccessor(values, TINYGLTF_TYPE_MAT4, 16, kNoTarget, false);
      model_.skins.push_back(std::move(out));
      continue;
    }
    tinygltf::Skin out;
    out.name = skin.name;
    for (const Index joint : skin.joints) out.joints.push_back(static_cast<int>(joint));
    out.skeleton = static_cast<int>(skin.skeleton);
    if (skin.has_inverse_bind_matrices) {
      if (skin.inverse_bind_matrices.size() != skin.joints.size()) {
        return Fail(Pointer("skins", i), "inverse bind matrix count differs from joint count");
      }
      std::vector<float> values;
      values.reserve(16 * skin.joints.size());
      for (std::size_t j = 0; j < skin.inverse_bind_matrices.size(); ++j) {
        const glm::mat4& m = skin.inverse_bind_matrices[j];
        for (int c = 0; c < 4; ++c) {
          const float expected = c == 3 ? 1.0f : 0.0f;
          if (!(std::fabs(m[c][3] - expected) <= kIbmLastRowTolerance)) {
            return Fail(Pointer("skins", i) + "/inverseBindMatrices/" + std::to_string(j),
                        "last row is not (0, 0, 0, 1)");
          }
          values.insert(values.end(), {m[c][0], m[c][1], m[c][2], expected});
        }
      }
      // No byteStride, no target: a plain IBM view.
      out.inverseBindMatrices = AddFloatAccessor(values, TINYGLTF_TYPE_MAT4, 16, kNoTarget, false);
    }
    model_.skins.push_back(std::move(out));
  }
  return Status::Ok();
}

const char* PathName(AnimationPath path) {
  switch (path) {
    case AnimationPath::kTranslation:
      return "translation";
    case AnimationPath::kRotation:
      return "rotation";
    case AnimationPath::kScale:
      return "scale";
    case AnimationPath::kWeights:
      return "weights";
  }
  return "translation";
}

const char* InterpolationName(Interpolation interpolation) {
  switch (interpolation) {
    case Interpolation::kLinear:
      return "LINEAR";
    case Interpolation::kStep:
      return "STEP";
    case Interpolation::kCubicSpline:
      return "CUBICSPLINE";
  }
  return "LINEAR";
}

Status ModelBuilder::AddAnimations() {
  for (std::size_t a = 0; a < asset_.animations.size(); ++a) {
    const AssetAnimation& animation = asset_.animations[a];
    // tinygltf drops animations without channels when writing; so do we, before adding data.
    if (animation.channels.empty()) continue;
    tinygltf::Animation out;
    out.name = animation.name;
    // The path each sampler is used for decides its output type (and rotation renormalising).
    std::vector<int> path_of(animation.samplers.size(), -1);
    for (const AssetAnimationChannel& channel : animation.channels) {
      if (channel.sampler >= 0 && static_cast<std::size_t>(channel.sampler) < path_of.size()) {
        path_of[static_cast<std::size_t>(channel.sampler)] = static_cast<int>(channel.path);
      }
    }
    for (std::size_t s = 0; s < animation.samplers.size(); ++s) {
      const AssetAnimationSampler& sampler = animation.samplers[s];
      const std::string pointer = Pointer("animations", a) + Pointer("samplers", s);
      if (sampler.times.empty() || sampler.components <= 0) {
        return Fail(pointer, "sampler has no keyframes");
      }
      const bool cubic = sampler.interpolation == Interpolation::kCubicSpline;
      const std::size_t comps = static_cast<std::size_t>(sampler.components);
      const std::size_t per_key = comps * (cubic ? 3 : 1);
      if (sampler.values.size() != per_key * sampler.times.size()) {
        return Fail(pointer, "value count does not match keyframe count");
      }
      tinygltf::AnimationSampler out_sampler;
      out_sampler.input =
          AddFloatAccessor(sampler.times, TINYGLTF_TYPE_SCALAR, 1, kNoTarget, /*bounds=*/true);
      std::vector<float> values = sampler.values;
      const bool weights_path = path_of[s] == static_cast<int>(AnimationPath::kWeights);
      const int components = weights_path || (comps != 3 && comps != 4) ? 1 : sampler.components;
      const int type = components == 3   ? TINYGLTF_TYPE_VEC3
                       : components == 4 ? TINYGLTF_TYPE_VEC4
                                         : TINYGLTF_TYPE_SCALAR;
      if (path_of[s] == static_cast<int>(AnimationPath::kRotation)) {
        if (comps != 4) return Fail(pointer, "rotation sampler without 4 components");
        for (std::size_t k = 0; k < sampler.times.size(); ++k) {
          // Only the value quaternions (not the cubic spline tangents) are unit.
          float* q = &values[k * per_key + (cubic ? 4 : 0)];
          const double len =
              std::sqrt(static_cast<double>(q[0]) * q[0] + static_cast<double>(q[1]) * q[1] +
                        static_cast<double>(q[2]) * q[2] + static_cast<double>(q[3]) * q[3]);
          if (!(len > 0.0)) return Fail(pointer, "zero rotation quaternion");
          for (int c = 0; c < 4; ++c) q[c] = static_cast<float>(q[c] / len);
        }
      }
      out_sampler.output = AddFloatAccessor(values, type, components, kNoTarget, false);
      out_sampler.interpolation = InterpolationName(sampler.interpolation);
      out.samplers.push_back(std::move(out_sampler));
    }
    for (const AssetAnimationChannel& channel : animation.channels) {
      tinygltf::AnimationChannel out_channel;
      out_channel.sampler = static_cast<int>(channel.sampler);
      out_channel.target_node = static_cast<int>(channel.node);
      if (channel.path == AnimationPath::kWeights && channel.node >= 0 &&
          static_cast<std::size_t>(channel.node) < mesh_child_.size() &&
          mesh_child_[static_cast<std::size_t>(channel.node)] >= 0) {
        out_channel.target_node = mesh_child_[static_cast<std::size_t>(channel.node)];
      }
      out_channel.target_path = PathName(channel.path);
      out.channels.push_back(std::move(out_channel));
    }
    model_.animations.push_back(std::move(out));
  }
  return Status::Ok();
}

Status ModelBuilder::Build() {
  model_.asset.version = "2.0";
  model_.asset.generator = options_.generator;
  model_.asset.copyright = asset_.copyright;

  if (options_.quantize) {
    grid_ = gltf_quantize::ChoosePositionGrid(asset_);
    report_.quantized = true;
    report_.position_bits = grid_.bits;
    report_.position_step = grid_.step;
    extensions_used_.insert("KHR_mesh_quantization");
  }
  Status status = AddMaterials();
  if (!status.ok()) return status;
  AddTexturesAndImages(&status);
  if (!status.ok()) return status;
  AddNodesAndScenes();
  status = AddMeshes();
  if (!status.ok()) return status;
  status = AddSkins();
  if (!status.ok()) return status;
  status = AddAnimations();
  if (!status.ok()) return status;

  if (!options_.dsurf_bytes.empty()) {
    const int view = AddView(options_.dsurf_bytes.data(), options_.dsurf_bytes.size(), kNoTarget);
    tinygltf::Value::Object extension;
    extension["bufferView"] = tinygltf::Value(view);
    model_.extensions[kDsurfGltfExtension] = tinygltf::Value(std::move(extension));
    extensions_used_.insert(kDsurfGltfExtension);
  }
  model_.extensionsUsed.assign(extensions_used_.begin(), extensions_used_.end());
  if (options_.quantize) model_.extensionsRequired.push_back("KHR_mesh_quantization");

  if (!bin_.empty()) {
    while (bin_.size() % 4 != 0) bin_.push_back(0);
    if (bin_.size() > std::numeric_limits<std::uint32_t>::max() - 1024u) {
      return Status::Unsupported(Source() + ": binary data exceeds 4 GiB");
    }
    tinygltf::Buffer buffer;
    buffer.data = std::move(bin_);
    model_.buffers.push_back(std::move(buffer));
  }
  return Status::Ok();
}

std::uint32_t ReadU32(const std::string& bytes, std::size_t offset) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) {
    v = (v << 8) | static_cast<unsigned char>(bytes[offset + static_cast<std::size_t>(i)]);
  }
  return v;
}

}  // namespace

Status SerializeGltf(const Asset& asset, const GltfExportOptions& options, bool binary,
                     std::string* bytes, GltfExportReport* report) {
  bytes->clear();
  GltfExportReport local_report;
  if (report == nullptr) report = &local_report;
  *report = GltfExportReport();
  const std::string source = asset.source.empty() ? "<asset>" : asset.source;
  const Status valid = ValidateAsset(asset);
  if (!valid.ok()) {
    // ValidateAsset names asset.source already; add it if an implementation did not.
    if (valid.message().rfind(source, 0) == 0) return valid;
    return valid.WithContext(source);
  }
  try {
    ModelBuilder builder(asset, options, report);
    const Status status = builder.Build();
    if (!status.ok()) return status;
    tinygltf::TinyGLTF writer;
    std::ostringstream stream;
    // The return value is always true (tinygltf #365): check the stream and the bytes.
    // Compression rewrites a GLB (tinygltf cannot write a buffer without data), then turns
    // it into a .gltf if asked.
    const bool glb = binary || options.compress;
    writer.WriteGltfSceneToStream(&builder.model(), stream, /*prettyPrint=*/!glb, glb);
    if (!stream) return Status::Internal(source + ": writing the glTF stream failed");
    *bytes = stream.str();
    if (options.compress) {
      std::string packed;
      gltf_meshopt::CompressStats stats;
      const Status s = gltf_meshopt::CompressGlb(
          *bytes, binary, options.quantize ? kExponentialFilterBits : 0, &packed, &stats);
      report->bytes_before_compression = stats.before;
      report->bytes_after_compression = stats.after;
      report->filtered_target_accessors = stats.filtered_views;
      report->max_filtered_target_error = stats.max_filter_error;
      if (!s.ok()) {
        bytes->clear();
        return s.WithContext(source);
      }
      report->compressed = true;
      *bytes = std::move(packed);
    }
  } catch (const std::exception& e) {
    bytes->clear();
    return Status::InvalidInput(source + ": glTF serialisation failed: " + e.what());
  }
  if (binary) {
    if (bytes->size() < 20 || bytes->compare(0, 4, "glTF") != 0 ||
        ReadU32(*bytes, 8) != bytes->size()) {
      bytes->clear();
      return Status::Internal(source + ": tinygltf wrote a malformed GLB");
    }
  } else if (bytes->empty() || (*bytes)[0] != '{') {
    bytes->clear();
    return Status::Internal(source + ": tinygltf wrote no JSON");
  }
  return Status::Ok();
}

Status ExportGltf(const Asset& asset, const GltfExportOptions& options, const std::string& path,
                  GltfExportReport* report) {
  const std::string ext = LowerExtension(path);
  bool binary;
  if (ext == ".glb") {
    binary = true;
  } else if (ext == ".gltf") {
    binary = false;
  } else {
    return Status::Unsupported(path + ": unknown glTF file extension (use .glb or .gltf)");
  }
  std::string bytes;
  const Status status = SerializeGltf(asset, options, binary, &bytes, report);
  if (!status.ok()) return status;
  return WriteFileAtomically(path, bytes);
}

}  // namespace dermis

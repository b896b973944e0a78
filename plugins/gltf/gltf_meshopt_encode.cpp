// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// EXT_meshopt_compression encoding of a GLB with meshoptimizer (docs/gltf-compression.md,
// "Compression"). The extension's rules followed here: compressed data lives in a buffer with
// data, the bufferView keeps its uncompressed layout in a fallback buffer; a view's mode is
// ATTRIBUTES (byteStride a multiple of 4, at most 256), TRIANGLES (index triples, 2 or 4
// bytes) or INDICES; with the extension required, the fallback buffer needs no data.
#include "gltf_meshopt_encode.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "gltf_glb.h"

namespace dermis::gltf_meshopt {
namespace {

using Json = nlohmann::json;

constexpr std::uint64_t kElementArrayBuffer = 34963;
/// About what the extension object adds to a bufferView's JSON: a view is encoded only if it
/// saves more than that.
constexpr std::size_t kExtensionJsonBytes = 160;

std::size_t ComponentBytes(int type) {
  switch (type) {
    case 5120:
    case 5121:
      return 1;
    case 5122:
    case 5123:
      return 2;
    case 5125:
    case 5126:
      return 4;
    default:
      return 0;
  }
}

std::size_t Components(const std::string& type) {
  static const std::map<std::string, std::size_t> kCount = {
      {"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4}, {"MAT2", 4}, {"MAT3", 9}, {"MAT4", 16}};
  auto it = kCount.find(type);
  return it == kCount.end() ? 0 : it->second;
}

/// How one bufferView is encoded.
struct Plan {
  const char* mode = nullptr;  // null: copied as it is
  bool exponential = false;
  std::size_t stride = 0;
  std::size_t count = 0;
};

std::uint64_t U64(const Json& object, const char* key, std::uint64_t fallback) {
  auto it = object.find(key);
  return it != object.end() && it->is_number_unsigned() ? it->get<std::uint64_t>() : fallback;
}

}  // namespace

Status CompressGlb(const std::string& glb, bool binary, int exp_filter_bits, std::string* out,
                   CompressStats* stats) {
  *stats = CompressStats();
  std::string json_text, bin;
  Status s = gltf_glb::Split(glb, &json_text, &bin);
  if (!s.ok()) return s;
  Json doc = Json::parse(json_text, nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) return Status::Internal("GLB JSON does not parse");
  Json& views = doc["bufferViews"];
  if (!views.is_array()) views = Json::array();
  const std::size_t view_count = views.size();

  // Which accessors read each view, and which views something else reads.
  std::vector<std::vector<std::size_t>> readers(view_count);
  std::vector<bool> pinned(view_count, false);
  const Json& accessors = doc.contains("accessors") ? doc["accessors"] : Json::array();
  for (std::size_t a = 0; a < accessors.size(); ++a) {
    const std::uint64_t v = U64(accessors[a], "bufferView", view_count);
    if (v < view_count) readers[v].push_back(a);
    if (accessors[a].contains("sparse")) {
      for (const char* part : {"indices", "values"}) {
        const std::uint64_t p =
            U64(accessors[a]["sparse"].value(part, Json::object()), "bufferView", view_count);
        if (p < view_count) pinned[p] = true;
      }
    }
  }
  // Index accessors of non-triangle-list primitives cannot use TRIANGLES; float morph
  // NORMAL / TANGENT deltas may take the EXPONENTIAL filter.
  std::vector<bool> not_triangles(accessors.size(), false);
  std::vector<bool> exp_filter(accessors.size(), false);
  if (doc.contains("meshes")) {
    for (const Json& mesh : doc["meshes"]) {
      for (const Json& p : mesh.value("primitives", Json::array())) {
        const std::uint64_t i = U64(p, "indices", accessors.size());
        if (i < accessors.size() && U64(p, "mode", 4) != 4) not_triangles[i] = true;
        for (const Json& target : p.value("targets", Json::array())) {
          for (const char* name : {"NORMAL", "TANGENT"}) {
            const std::uint64_t a = U64(target, name, accessors.size());
            if (a < accessors.size() && accessors[a].value("componentType", 0) == 5126) {
              exp_filter[a] = exp_filter_bits > 0;
            }
          }
        }
      }
    }
  }

  std::vector<Plan> plans(view_count);
  for (std::size_t v = 0; v < view_count; ++v) {
    const Json& view = views[v];
    if (pinned[v] || readers[v].size() != 1 || U64(view, "buffer", 1) != 0) continue;
    const Json& acc = accessors[readers[v][0]];
    if (U64(acc, "byteOffset", 0) != 0) continue;
    const std::size_t component = ComponentBytes(acc.value("componentType", 0));
    const std::size_t components = Components(acc.value("type", std::string()));
    const std::size_t count = U64(acc, "count", 0);
    const std::size_t length = U64(view, "byteLength", 0);
    if (component == 0 || components == 0 || count == 0) continue;
    Plan plan;
    plan.count = count;
    if (U64(view, "target", 0) == kElementArrayBuffer) {
      if (components != 1 || (component != 2 && component != 4) || length != count * component) {
        continue;
      }
      plan.stride = component;
      plan.mode = !not_triangles[readers[v][0]] && count % 3 == 0 ? "TRIANGLES" : "INDICES";
    } else {
      const std::size_t stride = U64(view, "byteStride", component * components);
      if (stride % 4 != 0 || stride > 256 || length != count * stride) continue;
      plan.stride = stride;
      plan.mode = "ATTRIBUTES";
      plan.exponential = exp_filter[readers[v][0]] && stride == 4 * components;
    }
    plans[v] = plan;
  }

  std::string packed;        // buffer 0: kept views and encoded streams
  std::size_t fallback = 0;  // byteLength of buffer 1
  std::vector<unsigned char> encoded;
  std::vector<unsigned char> filtered;
  std::vector<float> check;
  std::vector<std::uint32_t> indices;
  bool any = false;
  for (std::size_t v = 0; v < view_count; ++v) {
    Json& view = views[v];
    const std::size_t offset = U64(view, "byteOffset", 0);
    const std::size_t length = U64(view, "byteLength", 0);
    if (U64(view, "buffer", 1) != 0 || offset > bin.size() || length > bin.size() - offset) {
      return Status::Internal("bufferView " + std::to_string(v) + " is outside the GLB buffer");
    }
    const auto* data = reinterpret_cast<const unsigned char*>(bin.data() + offset);
    const Plan& plan = plans[v];
    while (packed.size() % 4 != 0) packed.push_back('\0');
    if (plan.mode == nullptr) {
      view["byteOffset"] = packed.size();
      packed.append(reinterpret_cast<const char*>(data), length);
      continue;
    }
    std::size_t size = 0;
    if (std::strcmp(plan.mode, "ATTRIBUTES") == 0) {
      const unsigned char* source = data;
      if (plan.exponential) {
        // Floats as a shared 8-bit exponent per element and exp_filter_bits mantissas: the
        // decoder's filter gives back float32; the error is measured on that round trip.
        std::vector<float> values(length / 4);
        std::memcpy(values.data(), data, length);
        filtered.resize(length);
        meshopt_encodeFilterExp(filtered.data(), plan.count, plan.stride, exp_filter_bits,
                                values.data());
        check.resize(length / 4);
        std::memcpy(check.data(), filtered.data(), length);
        meshopt_decodeFilterExp(check.data(), plan.count, plan.stride);
        for (std::size_t i = 0; i < values.size(); ++i) {
          stats->max_filter_error =
              std::max(stats->max_filter_error,
                       std::fabs(static_cast<double>(check[i]) - static_cast<double>(values[i])));
        }
        ++stats->filtered_views;
        source = filtered.data();
      }
      encoded.resize(meshopt_encodeVertexBufferBound(plan.count, plan.stride));
      size = meshopt_encodeVertexBuffer(encoded.data(), encoded.size(), source, plan.count,
                                        plan.stride);
    } else {
      indices.resize(plan.count);
      std::uint32_t top = 0;
      for (std::size_t i = 0; i < plan.count; ++i) {
        if (plan.stride == 2) {
          std::uint16_t x;
          std::memcpy(&x, data + 2 * i, 2);
          indices[i] = x;
        } else {
          std::memcpy(&indices[i], data + 4 * i, 4);
        }
        top = std::max(top, indices[i]);
      }
      if (std::strcmp(plan.mode, "TRIANGLES") == 0) {
        encoded.resize(meshopt_encodeIndexBufferBound(plan.count, std::size_t{top} + 1));
        size =
            meshopt_encodeIndexBuffer(encoded.data(), encoded.size(), indices.data(), plan.count);
      } else {
        encoded.resize(meshopt_encodeIndexSequenceBound(plan.count, std::size_t{top} + 1));
        size =
            meshopt_encodeIndexSequence(encoded.data(), encoded.size(), indices.data(), plan.count);
      }
    }
    if (size == 0) {
      return Status::Internal("meshoptimizer could not encode bufferView " + std::to_string(v));
    }
    if (size + kExtensionJsonBytes >= length) {
      // Not worth it (small views: animation keys, tiny meshes): kept as it is.
      view["byteOffset"] = packed.size();
      packed.append(reinterpret_cast<const char*>(data), length);
      continue;
    }
    any = true;
    stats->before += length;
    stats->after += size;
    Json ext = {{"buffer", 0},         {"byteOffset", packed.size()},
                {"byteLength", size},  {"byteStride", plan.stride},
                {"count", plan.count}, {"mode", plan.mode}};
    if (plan.exponential) ext["filter"] = "EXPONENTIAL";
    packed.append(reinterpret_cast<const char*>(encoded.data()), size);
    while (fallback % 4 != 0) ++fallback;
    view["buffer"] = 1;
    view["byteOffset"] = fallback;
    fallback += length;
    view["extensions"]["EXT_meshopt_compression"] = ext;
  }
  while (packed.size() % 4 != 0) packed.push_back('\0');
  if (any) {
    Json& buffers = doc["buffers"];
    buffers[0]["byteLength"] = packed.size();
    buffers[1] = {{"byteLength", fallback},
                  {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}};
    for (const char* list : {"extensionsUsed", "extensionsRequired"}) {
      Json& names = doc[list];
      if (!names.is_array()) names = Json::array();
      if (std::find(names.begin(), names.end(), "EXT_meshopt_compression") == names.end()) {
        names.push_back("EXT_meshopt_compression");
      }
    }
  }
  if (binary) {
    *out = gltf_glb::Join(doc.dump(), packed);
  } else {
    if (!packed.empty()) {
      doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + gltf_glb::Base64(packed);
    }
    *out = doc.dump(2);
  }
  return Status::Ok();
}

}  // namespace dermis::gltf_meshopt

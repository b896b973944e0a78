// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Compressed glTF in: EXT_meshopt_compression bufferViews decoded with meshoptimizer's decoder
// (its vertex and index codecs and the three filters of the extension) and
// KHR_draco_mesh_compression primitives decoded with Draco (gltf_draco_decode.cpp), gathered
// with every other buffer into one plain GLB (docs/gltf-compression.md, "Import").
#include "gltf_decompress.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "gltf_draco_decode.h"
#include "gltf_glb.h"

namespace dermis::gltf_decompress {
namespace {

using Json = nlohmann::json;

constexpr const char* kMeshopt = "EXT_meshopt_compression";
constexpr const char* kDraco = "KHR_draco_mesh_compression";
/// The most bytes the decoded data of one file may take.
constexpr std::uint64_t kMaxDecodedBytes = std::uint64_t{1} << 31;

std::string Ptr(const char* array, std::size_t i) {
  return std::string("/") + array + "/" + std::to_string(i);
}

Status Bad(const std::string& pointer, const std::string& message) {
  return Status::InvalidInput(pointer + ": " + message);
}

bool U64(const Json& o, const char* key, std::uint64_t* v) {
  auto it = o.find(key);
  if (it == o.end() || !it->is_number_unsigned()) return false;
  *v = it->get<std::uint64_t>();
  return true;
}

std::uint64_t U64Or(const Json& o, const char* key, std::uint64_t fallback) {
  std::uint64_t v = fallback;
  U64(o, key, &v);
  return v;
}

std::string UrlDecode(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
      out.push_back(static_cast<char>(std::stoi(s.substr(i + 1, 2), nullptr, 16)));
      i += 2;
    } else {
      out.push_back(s[i]);
    }
  }
  return out;
}

void RemoveName(Json* doc, const char* list, const char* name) {
  auto it = doc->find(list);
  if (it == doc->end() || !it->is_array()) return;
  it->erase(std::remove(it->begin(), it->end(), Json(name)), it->end());
  if (it->empty()) doc->erase(list);
}

void Align(std::string* bin) {
  while (bin->size() % 8 != 0) bin->push_back('\0');
}

/// The bytes of every buffer (empty for a fallback buffer without data).
Status LoadBuffers(const Json& doc, const std::string& glb_bin, const std::string& base_dir,
                   std::vector<std::string>* data, std::vector<bool>* has_data) {
  const Json buffers = doc.value("buffers", Json::array());
  data->assign(buffers.size(), std::string());
  has_data->assign(buffers.size(), false);
  for (std::size_t b = 0; b < buffers.size(); ++b) {
    const Json& buffer = buffers[b];
    const std::string p = Ptr("buffers", b);
    std::uint64_t length = 0;
    if (!buffer.is_object() || !U64(buffer, "byteLength", &length)) {
      return Bad(p, "no byteLength");
    }
    auto uri = buffer.find("uri");
    if (uri == buffer.end()) {
      if (b == 0 && !glb_bin.empty()) {
        (*data)[b] = glb_bin;
      } else if (buffer.contains("extensions") && buffer["extensions"].contains(kMeshopt)) {
        continue;  // the fallback buffer: no data by the extension's rules
      } else {
        return Bad(p, "buffer has no uri and no GLB data");
      }
    } else if (!uri->is_string()) {
      return Bad(p + "/uri", "not a string");
    } else {
      const std::string u = uri->get<std::string>();
      if (u.rfind("data:", 0) == 0) {
        const std::size_t comma = u.find(',');
        if (comma == std::string::npos || u.compare(comma - 7, 7, ";base64") != 0 ||
            !gltf_glb::DecodeBase64(u.substr(comma + 1), &(*data)[b])) {
          return Bad(p + "/uri", "not a base64 data URI");
        }
      } else {
        const std::string file = base_dir.empty() ? UrlDecode(u) : base_dir + "/" + UrlDecode(u);
        std::ifstream in(file, std::ios::binary);
        if (!in) {
          return Status::IoError(p + "/uri: external buffer '" + u + "' not found (looked for " +
                                 file + ")");
        }
        std::ostringstream ss;
        ss << in.rdbuf();
        (*data)[b] = ss.str();
      }
    }
    if ((*data)[b].size() < length) {
      return Bad(p, "byteLength " + std::to_string(length) + " exceeds its " +
                        std::to_string((*data)[b].size()) + " bytes of data");
    }
    (*data)[b].resize(length);
    (*has_data)[b] = true;
  }
  return Status::Ok();
}

/// Decodes one EXT_meshopt_compression bufferView into `out`.
Status DecodeMeshoptView(const Json& ext, const std::string& pointer,
                         const std::vector<std::string>& buffers, const std::vector<bool>& has_data,
                         std::uint64_t view_length, std::string* out) {
  std::uint64_t buffer = 0, offset = 0, length = 0, stride = 0, count = 0;
  if (!U64(ext, "buffer", &buffer) || !U64(ext, "byteLength", &length) ||
      !U64(ext, "byteStride", &stride) || !U64(ext, "count", &count) || !ext.contains("mode") ||
      !ext["mode"].is_string()) {
    return Bad(pointer, "needs buffer, byteLength, byteStride, count and mode");
  }
  U64(ext, "byteOffset", &offset);
  if (buffer >= buffers.size() || !has_data[buffer]) {
    return Bad(pointer, "buffer " + std::to_string(buffer) + " has no data");
  }
  const std::string& src = buffers[buffer];
  if (offset > src.size() || length > src.size() - offset) {
    return Bad(pointer, "byteOffset + byteLength exceeds buffer " + std::to_string(buffer));
  }
  if (stride == 0 || stride > 256 || count > kMaxDecodedBytes / stride) {
    return Bad(pointer, "byteStride " + std::to_string(stride) + " or count " +
                            std::to_string(count) + " out of range");
  }
  if (count * stride < view_length) {
    return Bad(pointer, "count * byteStride is smaller than the bufferView's byteLength");
  }
  out->assign(count * stride, '\0');
  const auto* data = reinterpret_cast<const unsigned char*>(src.data() + offset);
  const std::string mode = ext["mode"].get<std::string>();
  const std::string filter = ext.value("filter", std::string("NONE"));
  int rc = -1;
  if (mode == "ATTRIBUTES") {
    if (stride % 4 != 0) return Bad(pointer, "ATTRIBUTES byteStride is not a multiple of 4");
    rc = meshopt_decodeVertexBuffer(out->data(), count, stride, data, length);
    if (rc == 0 && filter == "OCTAHEDRAL") {
      if (stride != 4 && stride != 8) return Bad(pointer, "OCTAHEDRAL needs byteStride 4 or 8");
      meshopt_decodeFilterOct(out->data(), count, stride);
    } else if (rc == 0 && filter == "QUATERNION") {
      if (stride != 8) return Bad(pointer, "QUATERNION needs byteStride 8");
      meshopt_decodeFilterQuat(out->data(), count, stride);
    } else if (rc == 0 && filter == "EXPONENTIAL") {
      meshopt_decodeFilterExp(out->data(), count, stride);
    } else if (filter != "NONE") {
      return Bad(pointer, "unknown filter '" + filter + "'");
    }
  } else if (mode == "TRIANGLES" || mode == "INDICES") {
    if (stride != 2 && stride != 4) return Bad(pointer, mode + " byteStride must be 2 or 4");
    if (mode == "TRIANGLES") {
      if (count % 3 != 0) return Bad(pointer, "TRIANGLES count is not a multiple of 3");
      rc = meshopt_decodeIndexBuffer(out->data(), count, stride, data, length);
    } else {
      rc = meshopt_decodeIndexSequence(out->data(), count, stride, data, length);
    }
  } else {
    return Bad(pointer, "unknown mode '" + mode + "'");
  }
  if (rc != 0)
    return Bad(pointer, "meshopt data does not decode (code " + std::to_string(rc) + ")");
  out->resize(view_length);
  return Status::Ok();
}

/// Replaces a Draco primitive's extension by plain accessors into `bin`.
Status DecodeDracoPrimitive(Json* doc, Json* primitive, const std::string& pointer,
                            std::string* bin) {
  const Json& ext = (*primitive)["extensions"][kDraco];
  std::uint64_t view = 0;
  Json& views = (*doc)["bufferViews"];
  if (!U64(ext, "bufferView", &view) || view >= views.size() || !ext.contains("attributes") ||
      !ext["attributes"].is_object()) {
    return Bad(pointer, "needs a valid bufferView and attributes");
  }
  const std::uint64_t offset = U64Or(views[view], "byteOffset", 0);
  const std::uint64_t length = U64Or(views[view], "byteLength", 0);
  if (offset > bin->size() || length > bin->size() - offset) {
    return Bad(Ptr("bufferViews", view), "outside its buffer");
  }
  Json& accessors = (*doc)["accessors"];
  std::map<std::string, gltf_draco::AttributeRequest> requests;
  static const std::map<std::string, int> kComponents = {
      {"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4}};
  for (auto it = ext["attributes"].begin(); it != ext["attributes"].end(); ++it) {
    std::uint64_t acc = 0;
    if (!(*primitive)["attributes"].contains(it.key()) ||
        !U64((*primitive)["attributes"], it.key().c_str(), &acc) || acc >= accessors.size() ||
        !it.value().is_number_unsigned()) {
      return Bad(pointer + "/attributes/" + it.key(), "no accessor or id for the attribute");
    }
    const Json& a = accessors[acc];
    auto type = kComponents.find(a.value("type", std::string()));
    if (type == kComponents.end()) return Bad(Ptr("accessors", acc), "type is not SCALAR..VEC4");
    requests[it.key()] = {it.value().get<int>(), a.value("componentType", 0), type->second};
  }
  gltf_draco::DecodedPrimitive decoded;
  Status s = gltf_draco::DecodePrimitive(bin->substr(offset, length), requests, &decoded);
  if (!s.ok()) return Bad(pointer, s.message());
  for (const auto& [name, data] : decoded.attributes) {
    const std::uint64_t acc = (*primitive)["attributes"][name].get<std::uint64_t>();
    Align(bin);
    Json v = {{"buffer", 0}, {"byteOffset", bin->size()}, {"byteLength", data.size()}};
    const std::size_t element =
        data.empty() ? 0 : data.size() / std::max<std::size_t>(decoded.count, 1);
    Json& a = accessors[acc];
    const std::size_t tight =
        static_cast<std::size_t>(requests[name].components) *
        (a.value("componentType", 0) == 5126 || a.value("componentType", 0) == 5125 ? 4
         : a.value("componentType", 0) >= 5122                                      ? 2
                                                                                    : 1);
    if (element != tight) v["byteStride"] = element;
    v["target"] = 34962;
    bin->append(data);
    views.push_back(v);
    a["bufferView"] = views.size() - 1;
    a["byteOffset"] = 0;
    a["count"] = decoded.count;
  }
  Align(bin);
  Json v = {{"buffer", 0},
            {"byteOffset", bin->size()},
            {"byteLength", decoded.indices.size() * 4},
            {"target", 34963}};
  bin->append(reinterpret_cast<const char*>(decoded.indices.data()), decoded.indices.size() * 4);
  views.push_back(v);
  Json index = {{"bufferView", views.size() - 1},
                {"componentType", 5125},
                {"count", decoded.indices.size()},
                {"type", "SCALAR"}};
  std::uint64_t old = 0;
  if (U64(*primitive, "indices", &old) && old < accessors.size()) {
    accessors[old] = index;
  } else {
    accessors.push_back(index);
    (*primitive)["indices"] = accessors.size() - 1;
  }
  (*primitive)["extensions"].erase(kDraco);
  if ((*primitive)["extensions"].empty()) primitive->erase("extensions");
  return Status::Ok();
}

}  // namespace

bool UsesCompression(const Json& doc) {
  auto used = doc.find("extensionsUsed");
  if (used == doc.end() || !used->is_array()) return false;
  return std::find(used->begin(), used->end(), Json(kMeshopt)) != used->end() ||
         std::find(used->begin(), used->end(), Json(kDraco)) != used->end();
}

Status Decompress(const Json& source, const std::string& bin, const std::string& base_dir,
                  std::string* glb) {
  Json doc = source;
  std::vector<std::string> buffers;
  std::vector<bool> has_data;
  Status s = LoadBuffers(doc, bin, base_dir, &buffers, &has_data);
  if (!s.ok()) return s;
  // One BIN chunk: every buffer with data, then the decoded views.
  std::string out;
  std::vector<std::uint64_t> base(buffers.size(), 0);
  for (std::size_t b = 0; b < buffers.size(); ++b) {
    Align(&out);
    base[b] = out.size();
    out += buffers[b];
  }
  Json& views = doc["bufferViews"];
  if (!views.is_array()) views = Json::array();
  std::string decoded;
  for (std::size_t v = 0; v < views.size(); ++v) {
    Json& view = views[v];
    const std::string p = Ptr("bufferViews", v);
    std::uint64_t buffer = 0, length = 0;
    if (!view.is_object() || !U64(view, "buffer", &buffer) || buffer >= buffers.size() ||
        !U64(view, "byteLength", &length)) {
      return Bad(p, "needs a valid buffer and byteLength");
    }
    const bool meshopt = view.contains("extensions") && view["extensions"].contains(kMeshopt);
    if (meshopt) {
      s = DecodeMeshoptView(view["extensions"][kMeshopt], p + "/extensions/" + kMeshopt, buffers,
                            has_data, length, &decoded);
      if (!s.ok()) return s;
      if (out.size() + decoded.size() > kMaxDecodedBytes) {
        return Bad(p, "decoded data exceeds 2 GiB");
      }
      Align(&out);
      view["byteOffset"] = out.size();
      out += decoded;
      view["extensions"].erase(kMeshopt);
      if (view["extensions"].empty()) view.erase("extensions");
    } else {
      if (!has_data[buffer]) {
        return Bad(p, "refers to the fallback buffer " + std::to_string(buffer) +
                          " without EXT_meshopt_compression");
      }
      const std::uint64_t offset = U64Or(view, "byteOffset", 0);
      if (offset > buffers[buffer].size() || length > buffers[buffer].size() - offset) {
        return Bad(p, "byteOffset + byteLength exceeds buffer " + std::to_string(buffer));
      }
      view["byteOffset"] = base[buffer] + offset;
    }
    view["buffer"] = 0;
  }
  if (doc.contains("meshes")) {
    for (std::size_t m = 0; m < doc["meshes"].size(); ++m) {
      Json& prims = doc["meshes"][m]["primitives"];
      if (!prims.is_array()) continue;
      for (std::size_t i = 0; i < prims.size(); ++i) {
        if (!prims[i].contains("extensions") || !prims[i]["extensions"].contains(kDraco)) continue;
        s = DecodeDracoPrimitive(&doc, &prims[i],
                                 Ptr("meshes", m) + Ptr("primitives", i) + "/extensions/" + kDraco,
                                 &out);
        if (!s.ok()) return s;
      }
    }
  }
  Align(&out);
  doc["buffers"] = Json::array({Json{{"byteLength", out.size()}}});
  for (const char* list : {"extensionsUsed", "extensionsRequired"}) {
    RemoveName(&doc, list, kMeshopt);
    RemoveName(&doc, list, kDraco);
  }
  *glb = gltf_glb::Join(doc.dump(), out);
  return Status::Ok();
}

}  // namespace dermis::gltf_decompress

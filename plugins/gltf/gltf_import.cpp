// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// glTF 2.0 import. tinygltf 2.7 parses the container (JSON, GLB chunks, buffers and image
// files); every accessor is decoded here, with bounds checks and memcpy reads, so that strided,
// normalised, sparse and quantised data all come out as plain floats.
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "dermis/asset/asset_validate.h"
#include "dermis/core/file_io.h"
#include "dermis/core/limits.h"
#include "dermis/plugins/gltf.h"
#include "gltf_decompress.h"
#include "gltf_glb.h"

namespace dermis {
namespace {

using Json = nlohmann::json;

constexpr std::uint32_t kGlbMagic = 0x46546C67u;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534Au;
constexpr std::uint32_t kChunkBin = 0x004E4942u;
/// Upper bound on the number of decoded values of one accessor without a bufferView (a count
/// that no data backs must not make us allocate gigabytes).
constexpr std::uint64_t kMaxUnbackedValues = std::uint64_t{1} << 28;

std::string Str(std::uint64_t v) { return std::to_string(v); }
std::string Str(int v) { return std::to_string(v); }

/// A number as it would read in the file (shortest round-trip form).
std::string Num(double v) {
  std::ostringstream out;
  out.precision(17);
  out << v;
  return out.str();
}

std::string Ptr(const char* array, std::size_t i) {
  return std::string("/") + array + "/" + std::to_string(i);
}

std::uint32_t ReadU32(const std::string& bytes, std::size_t offset) {
  std::uint32_t v = 0;
  std::memcpy(&v, bytes.data() + offset, 4);
  return v;  // GLB is little-endian, as is every platform we build for.
}

std::string UrlDecode(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size() && hex(s[i + 1]) >= 0 && hex(s[i + 2]) >= 0) {
      out.push_back(static_cast<char>(hex(s[i + 1]) * 16 + hex(s[i + 2])));
      i += 2;
    } else {
      out.push_back(s[i]);
    }
  }
  return out;
}

bool StartsWith(const std::string& s, const char* prefix) {
  return s.compare(0, std::strlen(prefix), prefix) == 0;
}

std::string GuessMimeType(const std::string& b) {
  if (StartsWith(b, "\x89PNG\r\n\x1a\n")) return "image/png";
  if (StartsWith(b, "\xFF\xD8\xFF")) return "image/jpeg";
  if (b.size() >= 12 && StartsWith(b, "RIFF") && b.compare(8, 4, "WEBP") == 0) {
    return "image/webp";
  }
  if (StartsWith(b, "\xABKTX 20\xBB\r\n\x1A\n")) return "image/ktx2";
  return "";
}

/// Size in bytes of a glTF componentType allowed in accessors, 0 if not allowed.
std::size_t ComponentSize(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;
  }
}

const char* TypeName(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    case TINYGLTF_TYPE_MAT2:
      return "MAT2";
    case TINYGLTF_TYPE_MAT3:
      return "MAT3";
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
    default:
      return "?";
  }
}

/// Rows and columns of an accessor type (vectors have one column); false if unknown.
bool TypeShape(int type, std::size_t* rows, std::size_t* cols) {
  *cols = 1;
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      *rows = 1;
      return true;
    case TINYGLTF_TYPE_VEC2:
      *rows = 2;
      return true;
    case TINYGLTF_TYPE_VEC3:
      *rows = 3;
      return true;
    case TINYGLTF_TYPE_VEC4:
      *rows = 4;
      return true;
    case TINYGLTF_TYPE_MAT2:
      *rows = *cols = 2;
      return true;
    case TINYGLTF_TYPE_MAT3:
      *rows = *cols = 3;
      return true;
    case TINYGLTF_TYPE_MAT4:
      *rows = *cols = 4;
      return true;
    default:
      return false;
  }
}

/// Reads one component at `p` (memcpy, any alignment) and applies the glTF 2.0 (3.11)
/// normalisation formulas when `normalized`.
double ReadComponent(const unsigned char* p, int type, bool normalized) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      std::int8_t c;
      std::memcpy(&c, p, 1);
      return normalized ? std::max(c / 127.0, -1.0) : double(c);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      std::uint8_t c;
      std::memcpy(&c, p, 1);
      return normalized ? c / 255.0 : double(c);
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      std::int16_t c;
      std::memcpy(&c, p, 2);
      return normalized ? std::max(c / 32767.0, -1.0) : double(c);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      std::uint16_t c;
      std::memcpy(&c, p, 2);
      return normalized ? c / 65535.0 : double(c);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      std::uint32_t c;
      std::memcpy(&c, p, 4);
      return double(c);
    }
    default: {  // FLOAT (the only other type Decode() lets through)
      float c;
      std::memcpy(&c, p, 4);
      return double(c);
    }
  }
}

bool CheckedMulAdd(std::uint64_t a, std::uint64_t b, std::uint64_t c, std::uint64_t* r) {
  std::uint64_t m = 0;
  if (__builtin_mul_overflow(a, b, &m)) return false;
  return !__builtin_add_overflow(m, c, r);
}

/// A decoded accessor: count elements of `components` values each, row-major per element
/// (matrices column by column, as stored).
struct Decoded {
  std::vector<double> values;
  std::size_t count = 0;
  std::size_t components = 0;
  int type = 0;
  int component_type = 0;
};

/// Image loader handed to tinygltf: keeps the encoded bytes instead of decoding them.
struct ImageLoadLog {
  std::vector<bool> loaded;  ///< Per image index: bytes were handed to us.
};

bool KeepEncodedImage(tinygltf::Image* image, const int image_idx, std::string* /*err*/,
                      std::string* /*warn*/, int /*req_width*/, int /*req_height*/,
                      const unsigned char* bytes, int size, void* user) {
  // bufferView images: tinygltf hands us a pointer it did not bounds-check; the importer
  // takes those bytes from the buffer view itself.
  if (image->bufferView >= 0) return true;
  if (bytes != nullptr && size > 0) image->image.assign(bytes, bytes + size);
  auto* log = static_cast<ImageLoadLog*>(user);
  if (image_idx >= 0) {
    const std::size_t i = static_cast<std::size_t>(image_idx);
    if (log->loaded.size() <= i) log->loaded.resize(i + 1, false);
    log->loaded[i] = true;
  }
  return true;
}

/// Parses the digits after `prefix` in an attribute name ("TEXCOORD_12" -> 12), or -1.
int SetNumber(const std::string& name, const char* prefix) {
  const std::size_t n = std::strlen(prefix);
  if (name.compare(0, n, prefix) != 0 || name.size() == n || name.size() > n + 4) return -1;
  int v = 0;
  for (std::size_t i = n; i < name.size(); ++i) {
    if (name[i] < '0' || name[i] > '9') return -1;
    v = v * 10 + (name[i] - '0');
  }
  return v;
}

class GltfImporter {
 public:
  explicit GltfImporter(std::string path) : path_(std::move(path)) {}

  Status Run(Asset* out, std::string* dsurf_bytes);

 private:
  Status Fail(const std::string& pointer, const std::string& message,
              StatusCode code = StatusCode::kInvalidInput) const {
    return Status(code, path_ + ": " + pointer + ": " + message);
  }
  /// A fault of the file as a whole (container, JSON syntax): no JSON pointer to give.
  Status FailFile(const std::string& message, StatusCode code = StatusCode::kInvalidInput) const {
    return Status(code, path_ + ": " + message);
  }

  Status Load();
  Status CheckJsonDepth(std::string_view json) const;
  Status Charge(const std::string& pointer, std::uint64_t values) const;
  Status CheckGlbHeader(const std::string& bytes, std::string* json_text) const;
  Status CheckDocument();
  Status CheckExternalUri(const std::string& pointer, const std::string& uri,
                          const char* what) const;

  Status View(int index, const std::string& from, const unsigned char** data,
              std::size_t* size) const;
  Status Decode(int index, const std::string& from, Decoded* out) const;
  Status DecodeRaw(int index, const std::string& from, Decoded* out) const;
  struct Layout;
  Status ReadElement(const unsigned char* p, const Layout& layout, const std::string& pointer,
                     std::size_t e, double* dst) const;
  Status ApplySparse(const tinygltf::Accessor& acc, const Layout& layout, const std::string& ap,
                     Decoded* out) const;
  Status DecodeTyped(int index, const std::string& from, std::initializer_list<int> types,
                     Decoded* out) const;

  Status ImportMeshes(Asset* asset) const;
  Status DecodeAttribute(int accessor, const std::string& pointer, std::initializer_list<int> types,
                         std::size_t n, Decoded* d) const;
  Status ImportSkinAttributes(const std::string& pp, const std::map<int, int>& joint_sets,
                              const std::map<int, int>& weight_sets, std::size_t n,
                              AssetPrimitive* out) const;
  Status ImportIndices(const std::string& pp, int indices, std::size_t n,
                       AssetPrimitive* out) const;
  Status ImportTargets(const std::string& pp, const tinygltf::Primitive& p, std::size_t n,
                       AssetPrimitive* out) const;
  Status ImportPrimitive(const std::string& pp, const tinygltf::Primitive& p,
                         AssetPrimitive* out) const;
  Status ImportMaterials(Asset* asset) const;
  Status ImportImages(Asset* asset) const;
  Status ImportNodes(Asset* asset) const;
  Status ImportSkins(Asset* asset) const;
  Status CheckJointIndices(const Asset& asset) const;
  Status ImportAnimations(Asset* asset) const;
  Status ImportSamplers(const tinygltf::Animation& anim, const std::string& ap, AssetAnimation* out,
                        std::vector<Decoded>* outputs) const;
  Status ImportChannels(const tinygltf::Animation& anim, const std::string& ap,
                        const std::vector<Decoded>& outputs, AssetAnimation* out,
                        std::vector<int>* components) const;
  Status SetSamplerValues(const std::string& ap, const std::vector<Decoded>& outputs,
                          std::vector<int>* components, AssetAnimation* out) const;
  Status ImportDsurf(std::string* bytes) const;

  std::string path_;
  std::string base_dir_;
  Json doc_;
  tinygltf::Model model_;
  ImageLoadLog image_log_;
  std::uint64_t budget_bytes_ = limits::kImportBudgetBaseBytes;
  mutable std::uint64_t decoded_bytes_ = 0;  // every decode counts, repeated ones too
};

Status GltfImporter::Charge(const std::string& pointer, std::uint64_t values) const {
  const std::uint64_t bytes = values > (std::uint64_t{1} << 60) ? ~std::uint64_t{0} : values * 8;
  if (bytes > budget_bytes_ || decoded_bytes_ > budget_bytes_ - bytes) {
    return Fail(pointer, "decoding " + Str(values) +
                             " more values would pass the import budget of " + Str(budget_bytes_) +
                             " decoded bytes for this file (" + Str(decoded_bytes_) +
                             " decoded so far): refused");
  }
  decoded_bytes_ += bytes;
  return Status::Ok();
}

Status GltfImporter::CheckGlbHeader(const std::string& bytes, std::string* json_text) const {
  const std::uint64_t size = bytes.size();
  if (size < 12) {
    return FailFile("truncated GLB: " + Str(size) + " bytes, the header alone needs 12");
  }
  if (ReadU32(bytes, 0) != kGlbMagic) return FailFile("not a GLB file (bad magic)");
  const std::uint32_t version = ReadU32(bytes, 4);
  if (version != 2) {
    return FailFile("GLB version " + Str(std::uint64_t{version}) + " is not supported",
                    StatusCode::kUnsupported);
  }
  const std::uint64_t length = ReadU32(bytes, 8);
  if (length != size) {
    return FailFile("GLB header length " + Str(length) + " does not match the file size " +
                    Str(size) + " (truncated or padded file)");
  }
  if (size < 20) return FailFile("truncated GLB: no JSON chunk header");
  const std::uint64_t json_length = ReadU32(bytes, 12);
  if (ReadU32(bytes, 16) != kChunkJson) return FailFile("the first GLB chunk is not JSON");
  if (json_length == 0 || 20 + json_length > size) {
    return FailFile("GLB JSON chunk length " + Str(json_length) + " overflows the file (" +
                    Str(size) + " bytes)");
  }
  std::uint64_t offset = 20 + json_length;
  if (offset < size) {
    if (offset + 8 > size) return FailFile("truncated GLB: incomplete BIN chunk header");
    const std::uint64_t bin_length = ReadU32(bytes, static_cast<std::size_t>(offset));
    const std::uint32_t bin_type = ReadU32(bytes, static_cast<std::size_t>(offset + 4));
    if (bin_type != kChunkBin) return FailFile("the second GLB chunk is not BIN");
    if (offset + 8 + bin_length > size) {
      return FailFile("GLB BIN chunk length " + Str(bin_length) + " overflows the file (" +
                      Str(size) + " bytes)");
    }
    if (bin_length % 4 != 0 || bin_length == 0) {
      return FailFile("GLB BIN chunk length " + Str(bin_length) +
                      " is not a positive multiple of 4");
    }
  }
  *json_text = bytes.substr(20, static_cast<std::size_t>(json_length));
  return Status::Ok();
}

Status GltfImporter::CheckExternalUri(const std::string& pointer, const std::string& uri,
                                      const char* what) const {
  if (StartsWith(uri, "data:")) return Status::Ok();
  const std::string file = base_dir_.empty() ? UrlDecode(uri) : base_dir_ + "/" + UrlDecode(uri);
  std::ifstream probe(file, std::ios::binary);
  if (!probe) {
    return Fail(
        pointer,
        std::string("external ") + what + " '" + uri + "' not found (looked for " + file + ")",
        StatusCode::kIoError);
  }
  return Status::Ok();
}

Status GltfImporter::CheckDocument() {
  if (!doc_.is_object()) return FailFile("the glTF root is not a JSON object");
  for (const char* array : {"buffers", "images"}) {
    auto it = doc_.find(array);
    if (it == doc_.end() || !it->is_array()) continue;
    for (std::size_t i = 0; i < it->size(); ++i) {
      const Json& o = (*it)[i];
      if (!o.is_object()) continue;
      auto uri = o.find("uri");
      if (uri == o.end() || !uri->is_string()) continue;
      Status s = CheckExternalUri(Ptr(array, i) + "/uri", uri->get<std::string>(),
                                  array[0] == 'b' ? "buffer" : "image");
      if (!s.ok()) return s;
    }
  }
  // tinygltf hands image bufferViews to the image loader without a bounds check: check them
  // against the declared buffer byteLength (tinygltf makes buffer data exactly that long).
  auto images = doc_.find("images");
  auto views = doc_.find("bufferViews");
  auto buffers = doc_.find("buffers");
  if (images != doc_.end() && images->is_array() && views != doc_.end() && views->is_array() &&
      buffers != doc_.end() && buffers->is_array()) {
    for (std::size_t i = 0; i < images->size(); ++i) {
      const Json& image = (*images)[i];
      if (!image.is_object() || !image.contains("bufferView")) continue;
      const Json& v = image.at("bufferView");
      if (!v.is_number_unsigned() || v.get<std::uint64_t>() >= views->size()) continue;
      const std::size_t k = static_cast<std::size_t>(v.get<std::uint64_t>());
      const Json& view = (*views)[k];
      if (!view.is_object()) continue;
      const Json offset = view.value("byteOffset", Json(std::uint64_t{0}));
      const Json length = view.value("byteLength", Json(std::uint64_t{0}));
      const Json buffer = view.value("buffer", Json(-1));
      if (!offset.is_number_unsigned() || !length.is_number_unsigned() ||
          !buffer.is_number_unsigned() || buffer.get<std::uint64_t>() >= buffers->size()) {
        continue;
      }
      const Json& b = (*buffers)[static_cast<std::size_t>(buffer.get<std::uint64_t>())];
      const Json size = b.is_object() ? b.value("byteLength", Json(0)) : Json(0);
      const std::uint64_t o = offset.get<std::uint64_t>(), n = length.get<std::uint64_t>();
      if (size.is_number_unsigned() &&
          (o > size.get<std::uint64_t>() || n > size.get<std::uint64_t>() - o)) {
        return Fail(Ptr("bufferViews", k),
                    "byteOffset " + Str(o) + " + byteLength " + Str(n) + " exceeds buffer " +
                        Str(buffer.get<std::uint64_t>()) + " (used by " + Ptr("images", i) + ")");
      }
    }
  }
  auto req = doc_.find("extensionsRequired");
  if (req != doc_.end() && req->is_array()) {
    for (std::size_t i = 0; i < req->size(); ++i) {
      if (!(*req)[i].is_string()) continue;
      const std::string name = (*req)[i].get<std::string>();
      if (name == "KHR_draco_mesh_compression" || name == "EXT_meshopt_compression") {
        return Fail(Ptr("extensionsRequired", i),
                    "required extension " + name + " is not supported", StatusCode::kUnsupported);
      }
    }
  }
  return Status::Ok();
}

Status GltfImporter::Load() {
  std::string bytes;
  if (Status r = ReadFileBytes(path_, "a glTF file", &bytes); !r.ok()) return r;
  if (bytes.size() > std::numeric_limits<std::uint32_t>::max()) {
    return FailFile("file larger than 4 GiB", StatusCode::kUnsupported);
  }
  const std::size_t slash = path_.find_last_of('/');
  base_dir_ = slash == std::string::npos ? std::string() : path_.substr(0, slash);
  if (base_dir_.empty() && slash == 0) base_dir_ = "/";

  const bool ends_glb = path_.size() >= 4 && (path_.compare(path_.size() - 4, 4, ".glb") == 0 ||
                                              path_.compare(path_.size() - 4, 4, ".GLB") == 0);
  bool binary = bytes.size() >= 4 && ReadU32(bytes, 0) == kGlbMagic;
  std::string json_text;
  if (binary || ends_glb) {
    Status s = CheckGlbHeader(bytes, &json_text);
    if (!s.ok()) return s;
  } else {
    json_text = bytes;
  }
  // Depth before any JSON library sees the document: tinygltf converts values recursively and
  // a few kilobytes of brackets would overflow the stack.
  if (Status d = CheckJsonDepth(json_text); !d.ok()) return d;
  try {
    doc_ = Json::parse(json_text);
  } catch (const Json::exception& e) {
    return FailFile(std::string("invalid JSON: ") + e.what());
  }
  // Compressed files (EXT_meshopt_compression, KHR_draco_mesh_compression) are first decoded
  // into a plain GLB in memory (gltf_decompress.cpp), then read like any other.
  if (doc_.is_object() && gltf_decompress::UsesCompression(doc_)) {
    std::string json_chunk, bin_chunk, plain;
    if (binary) {
      Status split = gltf_glb::Split(bytes, &json_chunk, &bin_chunk);
      if (!split.ok()) return FailFile(split.message());
    }
    Status decoded = gltf_decompress::Decompress(doc_, bin_chunk, base_dir_, &plain);
    if (!decoded.ok()) return FailFile(decoded.message(), decoded.code());
    bytes = std::move(plain);
    binary = true;
    json_text = bytes.substr(20, ReadU32(bytes, 12));
    doc_ = Json::parse(json_text, nullptr, false);
    if (doc_.is_discarded()) return FailFile("decompressed JSON does not parse");
  }
  Status s = CheckDocument();
  if (!s.ok()) return s;
  if (auto nodes = doc_.find("nodes");
      nodes != doc_.end() && nodes->is_array() && nodes->size() > limits::kMaxNodes) {
    return Fail("/nodes", Str(std::uint64_t{nodes->size()}) + " nodes, more than the limit of " +
                              Str(limits::kMaxNodes));
  }

  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&KeepEncodedImage, &image_log_);
  std::string err, warn;
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const auto size = static_cast<unsigned int>(bytes.size());
  // tinygltf 2.7 fills `err` for valid files (a skin without inverseBindMatrices): only the
  // return value says whether loading failed.
  const bool ok =
      binary ? loader.LoadBinaryFromMemory(&model_, &err, &warn, data, size, base_dir_)
             : loader.LoadASCIIFromString(&model_, &err, &warn, json_text.data(), size, base_dir_);
  if (!ok) {
    std::string why = err.empty() ? warn : err;
    while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
    std::replace(why.begin(), why.end(), '\n', ';');
    return FailFile("tinygltf could not load the file: " + (why.empty() ? "no reason" : why));
  }
  // The decoded-bytes budget: proportional to the bytes the file brings (its own and its
  // buffers'), so a tiny file cannot ask for gigabytes of accessor values.
  std::uint64_t source_bytes = bytes.size();
  for (const tinygltf::Buffer& b : model_.buffers) source_bytes += b.data.size();
  budget_bytes_ =
      limits::kImportBudgetBaseBytes + limits::kImportBudgetBytesPerFileByte * source_bytes;
  return Status::Ok();
}

Status GltfImporter::CheckJsonDepth(std::string_view json) const {
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < json.size(); ++i) {
    const char c = json[i];
    if (in_string) {
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > limits::kMaxJsonDepth) {
        return FailFile("JSON nested deeper than " + Str(limits::kMaxJsonDepth) +
                        " levels (at byte " + Str(std::uint64_t{i}) + "): refused");
      }
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return Status::Ok();
}

Status GltfImporter::View(int index, const std::string& from, const unsigned char** data,
                          std::size_t* size) const {
  if (index < 0 || static_cast<std::size_t>(index) >= model_.bufferViews.size()) {
    return Fail(from, "bufferView " + Str(index) + " does not exist");
  }
  const std::string vp = Ptr("bufferViews", static_cast<std::size_t>(index));
  const tinygltf::BufferView& view = model_.bufferViews[static_cast<std::size_t>(index)];
  if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model_.buffers.size()) {
    return Fail(vp + "/buffer", "buffer " + Str(view.buffer) + " does not exist");
  }
  const std::vector<unsigned char>& buffer =
      model_.buffers[static_cast<std::size_t>(view.buffer)].data;
  if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset) {
    return Fail(vp, "byteOffset " + Str(view.byteOffset) + " + byteLength " + Str(view.byteLength) +
                        " exceeds buffer " + Str(view.buffer) + " (" + Str(buffer.size()) +
                        " bytes)");
  }
  *data = buffer.data() + view.byteOffset;
  *size = view.byteLength;
  return Status::Ok();
}

Status GltfImporter::Decode(int index, const std::string& from, Decoded* out) const {
  Status s = DecodeRaw(index, from, out);
  // Faults inside the accessor name it; add where it was used from.
  if (!s.ok() &&
      s.message().compare(0, path_.size() + 2 + from.size() + 1, path_ + ": " + from + ":") != 0) {
    return Status(s.code(), s.message() + " (used by " + from + ")");
  }
  return s;
}

// How an accessor's elements lie in bytes.
struct GltfImporter::Layout {
  std::size_t rows = 0, cols = 0;  // VEC3: 3 x 1, MAT4: 4 x 4
  std::size_t component_size = 0;
  std::size_t column_stride = 0;  // matrix columns start on 4-byte boundaries
  std::size_t element_size = 0;
  int component_type = 0;
  bool normalized = false;
};

// Reads element `e` at `p` into dst[0 .. rows * cols); float components must be finite.
Status GltfImporter::ReadElement(const unsigned char* p, const Layout& layout,
                                 const std::string& pointer, std::size_t e, double* dst) const {
  const bool is_float = layout.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT;
  for (std::size_t c = 0; c < layout.cols; ++c) {
    for (std::size_t r = 0; r < layout.rows; ++r) {
      const double v = ReadComponent(p + c * layout.column_stride + r * layout.component_size,
                                     layout.component_type, layout.normalized);
      if (is_float && !std::isfinite(v)) {
        return Fail(pointer, "element " + Str(std::uint64_t{e}) + " component " +
                                 Str(std::uint64_t{c * layout.rows + r}) + " is not finite");
      }
      dst[c * layout.rows + r] = v;
    }
  }
  return Status::Ok();
}

// Sparse substitution: `sparse.count` indices (unsigned, below the accessor's count) and values
// replace elements of the base.
Status GltfImporter::ApplySparse(const tinygltf::Accessor& acc, const Layout& layout,
                                 const std::string& ap, Decoded* out) const {
  const std::string sp = ap + "/sparse";
  const std::uint64_t count = acc.count;
  const int n = acc.sparse.count;
  if (n < 1 || static_cast<std::uint64_t>(n) > count) {
    return Fail(sp + "/count", "sparse count " + Str(n) + " is not in [1, " + Str(count) + "]");
  }
  const std::size_t sn = static_cast<std::size_t>(n);
  const int itype = acc.sparse.indices.componentType;
  const std::size_t isize = itype == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                            : itype == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                            : itype == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                              : 0;
  if (isize == 0) {
    return Fail(sp + "/indices/componentType",
                "sparse indices componentType " + Str(itype) + " is not an unsigned integer");
  }
  const unsigned char* idata = nullptr;
  std::size_t isz = 0;
  Status s = View(acc.sparse.indices.bufferView, sp + "/indices/bufferView", &idata, &isz);
  if (!s.ok()) return s;
  const int ioff = acc.sparse.indices.byteOffset;
  std::uint64_t iend = 0;
  if (ioff < 0 || !CheckedMulAdd(sn, isize, static_cast<std::uint64_t>(ioff), &iend) ||
      iend > isz) {
    return Fail(sp + "/indices",
                "byteOffset " + Str(ioff) + " + " + Str(n) + " indices exceed bufferView " +
                    Str(acc.sparse.indices.bufferView) + " (" + Str(isz) + " bytes)");
  }
  const unsigned char* vdata = nullptr;
  std::size_t vsz = 0;
  s = View(acc.sparse.values.bufferView, sp + "/values/bufferView", &vdata, &vsz);
  if (!s.ok()) return s;
  const int voff = acc.sparse.values.byteOffset;
  std::uint64_t vend = 0;
  if (voff < 0 ||
      !CheckedMulAdd(sn, layout.element_size, static_cast<std::uint64_t>(voff), &vend) ||
      vend > vsz) {
    return Fail(sp + "/values",
                "byteOffset " + Str(voff) + " + " + Str(n) + " values exceed bufferView " +
                    Str(acc.sparse.values.bufferView) + " (" + Str(vsz) + " bytes)");
  }
  for (std::size_t k = 0; k < sn; ++k) {
    const std::uint64_t target = static_cast<std::uint64_t>(
        ReadComponent(idata + static_cast<std::size_t>(ioff) + k * isize, itype, false));
    if (target >= count) {
      return Fail(sp + "/indices", "index " + Str(target) + " (entry " + Str(std::uint64_t{k}) +
                                       ") >= accessor count " + Str(count));
    }
    s = ReadElement(vdata + static_cast<std::size_t>(voff) + k * layout.element_size, layout,
                    ap + "/sparse/values", k,
                    out->values.data() + static_cast<std::size_t>(target) * out->components);
    if (!s.ok()) return s;
  }
  return Status::Ok();
}

Status GltfImporter::DecodeRaw(int index, const std::string& from, Decoded* out) const {
  if (index < 0 || static_cast<std::size_t>(index) >= model_.accessors.size()) {
    return Fail(from, "accessor " + Str(index) + " does not exist");
  }
  const std::string ap = Ptr("accessors", static_cast<std::size_t>(index));
  const tinygltf::Accessor& acc = model_.accessors[static_cast<std::size_t>(index)];
  Layout layout;
  layout.component_type = acc.componentType;
  layout.normalized = acc.normalized;
  layout.component_size = ComponentSize(acc.componentType);
  if (layout.component_size == 0) {
    return Fail(ap + "/componentType",
                "componentType " + Str(acc.componentType) + " is not allowed in glTF 2.0");
  }
  if (!TypeShape(acc.type, &layout.rows, &layout.cols)) {
    return Fail(ap + "/type", "unknown accessor type");
  }
  if (acc.normalized && (acc.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                         acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)) {
    return Fail(ap + "/normalized",
                "normalized is not allowed for componentType " + Str(acc.componentType));
  }
  // Matrix columns start on 4-byte boundaries (glTF 2.0, 3.6.2.4).
  layout.column_stride = layout.rows * layout.component_size;
  if (layout.cols > 1) layout.column_stride = (layout.column_stride + 3) / 4 * 4;
  layout.element_size = layout.column_stride * layout.cols;
  const std::size_t element_size = layout.element_size;
  const std::size_t components = layout.rows * layout.cols;
  const std::uint64_t count = acc.count;
  std::uint64_t total = 0;
  if (!CheckedMulAdd(count, components, 0, &total)) {
    return Fail(ap + "/count", "count " + Str(count) + " is too large");
  }
  const unsigned char* data = nullptr;
  std::uint64_t stride = element_size;
  if (acc.bufferView >= 0) {
    std::size_t size = 0;
    Status s = View(acc.bufferView, ap + "/bufferView", &data, &size);
    if (!s.ok()) return s;
    const tinygltf::BufferView& view = model_.bufferViews[static_cast<std::size_t>(acc.bufferView)];
    if (view.byteStride != 0 && view.byteStride < element_size) {
      return Fail(Ptr("bufferViews", static_cast<std::size_t>(acc.bufferView)) + "/byteStride",
                  "byteStride " + Str(view.byteStride) + " is smaller than the element size " +
                      Str(element_size) + " of accessor " + Str(index));
    }
    if (view.byteStride != 0) stride = view.byteStride;
    std::uint64_t end = 0;
    if (count > 0 &&
        (!CheckedMulAdd(count - 1, stride, element_size, &end) ||
         __builtin_add_overflow(end, std::uint64_t{acc.byteOffset}, &end) || end > size)) {
      return Fail(ap, "byteOffset " + Str(acc.byteOffset) + " + " + Str(count) +
                          " elements of stride " + Str(stride) + " exceed bufferView " +
                          Str(acc.bufferView) + " (" + Str(size) + " bytes)");
    }
  } else if (total > kMaxUnbackedValues) {
    return Fail(ap + "/count",
                "count " + Str(count) + " is too large for an accessor without bufferView");
  }
  if (Status b = Charge(ap, total); !b.ok()) return b;
  out->count = static_cast<std::size_t>(count);
  out->components = components;
  out->type = acc.type;
  out->component_type = acc.componentType;
  out->values.assign(static_cast<std::size_t>(total), 0.0);
  if (data != nullptr) {
    for (std::size_t e = 0; e < out->count; ++e) {
      Status s = ReadElement(data + acc.byteOffset + e * stride, layout, ap, e,
                             out->values.data() + e * components);
      if (!s.ok()) return s;
    }
  }
  return acc.sparse.isSparse ? ApplySparse(acc, layout, ap, out) : Status::Ok();
}

Status GltfImporter::DecodeTyped(int index, const std::string& from,
                                 std::initializer_list<int> types, Decoded* out) const {
  Status s = Decode(index, from, out);
  if (!s.ok()) return s;
  if (std::find(types.begin(), types.end(), out->type) == types.end()) {
    std::string expected;
    for (int t : types) expected += (expected.empty() ? "" : " or ") + std::string(TypeName(t));
    return Fail(from, "accessor " + Str(index) + " has type " + TypeName(out->type) +
                          ", expected " + expected);
  }
  return Status::Ok();
}

template <typename V>
std::vector<V> ToVectors(const Decoded& d) {
  std::vector<V> out(d.count);
  const std::size_t n = static_cast<std::size_t>(V::length());
  for (std::size_t i = 0; i < d.count; ++i) {
    for (std::size_t c = 0; c < n; ++c) {
      out[i][static_cast<typename V::length_type>(c)] =
          static_cast<float>(d.values[i * d.components + c]);
    }
  }
  return out;
}

// Decodes an attribute accessor of one of `types` that must have `n` elements (POSITION's).
Status GltfImporter::DecodeAttribute(int accessor, const std::string& pointer,
                                     std::initializer_list<int> types, std::size_t n,
                                     Decoded* d) const {
  Status st = DecodeTyped(accessor, pointer, types, d);
  if (!st.ok()) return st;
  if (d->count != n) {
    return Fail(pointer, "accessor " + Str(accessor) + " has " + Str(std::uint64_t{d->count}) +
                             " elements, POSITION has " + Str(std::uint64_t{n}));
  }
  return Status::Ok();
}

// JOINTS_n (integers in [0, 65535]) and WEIGHTS_n (non-negative), the weights of each vertex
// renormalised over all sets; all-zero rows stay zero.
Status GltfImporter::ImportSkinAttributes(const std::string& pp,
                                          const std::map<int, int>& joint_sets,
                                          const std::map<int, int>& weight_sets, std::size_t n,
                                          AssetPrimitive* out) const {
  const std::string atp = pp + "/attributes/";
  if (joint_sets.size() != weight_sets.size()) {
    return Fail(pp + "/attributes", Str(std::uint64_t{joint_sets.size()}) + " JOINTS_n sets but " +
                                        Str(std::uint64_t{weight_sets.size()}) + " WEIGHTS_n sets");
  }
  Decoded d;
  for (const auto& [k, accessor] : joint_sets) {
    const std::string jp = atp + "JOINTS_" + Str(k);
    Status s = DecodeAttribute(accessor, jp, {TINYGLTF_TYPE_VEC4}, n, &d);
    if (!s.ok()) return s;
    std::vector<glm::u16vec4> joints(n);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t c = 0; c < 4; ++c) {
        const double v = d.values[i * 4 + c];
        if (!(v >= 0.0 && v <= 65535.0 && v == std::floor(v))) {
          return Fail(jp, "vertex " + Str(std::uint64_t{i}) + " has joint index " + Num(v) +
                              ", not an integer in [0, 65535]");
        }
        joints[i][static_cast<glm::length_t>(c)] = static_cast<std::uint16_t>(v);
      }
    }
    out->joints.push_back(std::move(joints));
  }
  std::vector<std::vector<double>> raw_weights;
  for (const auto& [k, accessor] : weight_sets) {
    const std::string wp = atp + "WEIGHTS_" + Str(k);
    Status s = DecodeAttribute(accessor, wp, {TINYGLTF_TYPE_VEC4}, n, &d);
    if (!s.ok()) return s;
    for (std::size_t i = 0; i < d.values.size(); ++i) {
      if (d.values[i] < 0.0) {
        return Fail(wp, "vertex " + Str(std::uint64_t{i / 4}) + " has a negative weight");
      }
    }
    raw_weights.push_back(d.values);
  }
  out->weights.assign(raw_weights.size(), std::vector<glm::vec4>(n, glm::vec4(0.0f)));
  for (std::size_t i = 0; i < n && !raw_weights.empty(); ++i) {
    double sum = 0.0;
    for (const auto& w : raw_weights) sum += w[i * 4] + w[i * 4 + 1] + w[i * 4 + 2] + w[i * 4 + 3];
    const double scale = sum > 0.0 ? 1.0 / sum : 0.0;
    for (std::size_t set = 0; set < raw_weights.size(); ++set) {
      for (std::size_t c = 0; c < 4; ++c) {
        out->weights[set][i][static_cast<glm::length_t>(c)] =
            static_cast<float>(raw_weights[set][i * 4 + c] * scale);
      }
    }
  }
  return Status::Ok();
}

// The index accessor: unsigned integers below the vertex count `n`.
Status GltfImporter::ImportIndices(const std::string& pp, int indices, std::size_t n,
                                   AssetPrimitive* out) const {
  const std::string ip = pp + "/indices";
  Decoded d;
  Status s = DecodeTyped(indices, ip, {TINYGLTF_TYPE_SCALAR}, &d);
  if (!s.ok()) return s;
  if (d.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
      d.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      d.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
    return Fail(ip, "accessor " + Str(indices) + " has componentType " + Str(d.component_type) +
                        ", indices must be unsigned integers");
  }
  out->indices.resize(d.count);
  for (std::size_t i = 0; i < d.count; ++i) {
    const double v = d.values[i];  // an unsigned integer from the decoder
    if (v >= static_cast<double>(n)) {
      return Fail(ip, "index " + Str(static_cast<std::uint64_t>(v)) + " at position " +
                          Str(std::uint64_t{i}) + " >= vertex count " + Str(std::uint64_t{n}));
    }
    out->indices[i] = static_cast<std::uint32_t>(v);
  }
  return Status::Ok();
}

// Morph targets: POSITION, NORMAL and TANGENT deltas (other attributes are ignored).
Status GltfImporter::ImportTargets(const std::string& pp, const tinygltf::Primitive& p,
                                   std::size_t n, AssetPrimitive* out) const {
  Decoded d;
  for (std::size_t t = 0; t < p.targets.size(); ++t) {
    AssetMorphTarget target;
    const std::string tp = pp + "/targets/" + Str(std::uint64_t{t}) + "/";
    for (const auto& [name, accessor] : p.targets[t]) {
      if (name != "POSITION" && name != "NORMAL" && name != "TANGENT") continue;
      Status s = DecodeAttribute(accessor, tp + name, {TINYGLTF_TYPE_VEC3}, n, &d);
      if (!s.ok()) return s;
      std::vector<glm::vec3> deltas = ToVectors<glm::vec3>(d);
      if (name == "POSITION") target.positions = std::move(deltas);
      if (name == "NORMAL") target.normals = std::move(deltas);
      if (name == "TANGENT") target.tangents = std::move(deltas);
    }
    out->targets.push_back(std::move(target));
  }
  return Status::Ok();
}

Status GltfImporter::ImportPrimitive(const std::string& pp, const tinygltf::Primitive& p,
                                     AssetPrimitive* out) const {
  const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
  if (mode > 6) return Fail(pp + "/mode", "unknown primitive mode " + Str(mode));
  out->mode = static_cast<PrimitiveMode>(mode);
  out->material = p.material;
  const std::string atp = pp + "/attributes/";
  auto pos = p.attributes.find("POSITION");
  if (pos == p.attributes.end()) {
    return Fail(pp + "/attributes", "no POSITION attribute", StatusCode::kUnsupported);
  }
  Decoded d;
  Status s = DecodeTyped(pos->second, atp + "POSITION", {TINYGLTF_TYPE_VEC3}, &d);
  if (!s.ok()) return s;
  const std::size_t n = d.count;
  out->positions = ToVectors<glm::vec3>(d);

  // Attribute sets (TEXCOORD_n, ...) by set number; they must be numbered 0, 1, 2, ...
  std::map<std::string, std::map<int, int>> sets;
  for (const auto& [name, accessor] : p.attributes) {
    if (name == "NORMAL") {
      s = DecodeAttribute(accessor, atp + name, {TINYGLTF_TYPE_VEC3}, n, &d);
      if (!s.ok()) return s;
      out->normals = ToVectors<glm::vec3>(d);
    } else if (name == "TANGENT") {
      s = DecodeAttribute(accessor, atp + name, {TINYGLTF_TYPE_VEC4}, n, &d);
      if (!s.ok()) return s;
      out->tangents = ToVectors<glm::vec4>(d);
    } else {
      for (const char* prefix : {"TEXCOORD_", "COLOR_", "JOINTS_", "WEIGHTS_"}) {
        const int k = SetNumber(name, prefix);
        if (k >= 0) sets[prefix][k] = accessor;
      }
    }
  }
  for (const auto& [prefix, by_number] : sets) {
    int expected = 0;
    for (const auto& entry : by_number) {
      if (entry.first != expected) {
        return Fail(atp + prefix + Str(expected),
                    "missing (sets must be numbered from 0 without gaps)");
      }
      ++expected;
    }
  }
  for (const auto& [k, accessor] : sets["TEXCOORD_"]) {
    s = DecodeAttribute(accessor, atp + "TEXCOORD_" + Str(k), {TINYGLTF_TYPE_VEC2}, n, &d);
    if (!s.ok()) return s;
    out->texcoords.push_back(ToVectors<glm::vec2>(d));
  }
  for (const auto& [k, accessor] : sets["COLOR_"]) {
    s = DecodeAttribute(accessor, atp + "COLOR_" + Str(k), {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4},
                        n, &d);
    if (!s.ok()) return s;
    std::vector<glm::vec4> colors(n, glm::vec4(1.0f));
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t c = 0; c < d.components; ++c) {
        colors[i][static_cast<glm::length_t>(c)] =
            static_cast<float>(d.values[i * d.components + c]);
      }
    }
    out->colors.push_back(std::move(colors));
  }
  s = ImportSkinAttributes(pp, sets["JOINTS_"], sets["WEIGHTS_"], n, out);
  if (!s.ok()) return s;
  if (p.indices >= 0) {
    s = ImportIndices(pp, p.indices, n, out);
    if (!s.ok()) return s;
  }
  return ImportTargets(pp, p, n, out);
}

Status GltfImporter::ImportMeshes(Asset* asset) const {
  asset->meshes.resize(model_.meshes.size());
  for (std::size_t m = 0; m < model_.meshes.size(); ++m) {
    const tinygltf::Mesh& mesh = model_.meshes[m];
    AssetMesh& out = asset->meshes[m];
    out.name = mesh.name;
    for (std::size_t w = 0; w < mesh.weights.size(); ++w) {
      if (!std::isfinite(mesh.weights[w])) {
        return Fail(Ptr("meshes", m) + "/weights/" + Str(std::uint64_t{w}), "not finite");
      }
      out.weights.push_back(static_cast<float>(mesh.weights[w]));
    }
    out.primitives.resize(mesh.primitives.size());
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      Status s = ImportPrimitive(Ptr("meshes", m) + Ptr("primitives", p), mesh.primitives[p],
                                 &out.primitives[p]);
      if (!s.ok()) return s;
    }
  }
  return Status::Ok();
}

Status GltfImporter::ImportMaterials(Asset* asset) const {
  const Json* materials = nullptr;
  auto it = doc_.find("materials");
  if (it != doc_.end() && it->is_array()) materials = &*it;
  asset->materials.resize(model_.materials.size());
  for (std::size_t i = 0; i < model_.materials.size(); ++i) {
    asset->materials[i].name = model_.materials[i].name;
    // The material object exactly as written (all extensions and extras kept), compact, with
    // keys sorted (nlohmann::json objects are ordered maps): deterministic text.
    if (materials != nullptr && i < materials->size() && (*materials)[i].is_object()) {
      asset->materials[i].json = (*materials)[i].dump();
    }
  }
  asset->samplers.resize(model_.samplers.size());
  for (std::size_t i = 0; i < model_.samplers.size(); ++i) {
    const tinygltf::Sampler& s = model_.samplers[i];
    asset->samplers[i] = {s.name, s.magFilter, s.minFilter, s.wrapS, s.wrapT};
  }
  asset->textures.resize(model_.textures.size());
  for (std::size_t i = 0; i < model_.textures.size(); ++i) {
    const tinygltf::Texture& t = model_.textures[i];
    asset->textures[i] = {t.name, t.source, t.sampler};
  }
  return Status::Ok();
}

Status GltfImporter::ImportImages(Asset* asset) const {
  const Json* images = nullptr;
  auto it = doc_.find("images");
  if (it != doc_.end() && it->is_array()) images = &*it;
  asset->images.resize(model_.images.size());
  for (std::size_t i = 0; i < model_.images.size(); ++i) {
    const tinygltf::Image& image = model_.images[i];
    AssetImage& out = asset->images[i];
    out.name = image.name;
    if (image.bufferView >= 0) {
      const unsigned char* data = nullptr;
      std::size_t size = 0;
      Status s = View(image.bufferView, Ptr("images", i) + "/bufferView", &data, &size);
      if (!s.ok()) return s;
      out.bytes.assign(reinterpret_cast<const char*>(data), size);
    } else if (i < image_log_.loaded.size() && image_log_.loaded[i]) {
      out.bytes.assign(image.image.begin(), image.image.end());
    } else {
      return Fail(Ptr("images", i) + "/uri", "image '" + image.uri + "' could not be read",
                  StatusCode::kIoError);
    }
    out.mime_type = image.mimeType;
    if (out.mime_type.empty() && images != nullptr && i < images->size()) {
      const Json& o = (*images)[i];
      auto mime = o.is_object() ? o.find("mimeType") : o.end();
      if (o.is_object() && mime != o.end() && mime->is_string()) {
        out.mime_type = mime->get<std::string>();
      }
    }
    if (out.mime_type.empty()) out.mime_type = GuessMimeType(out.bytes);
  }
  return Status::Ok();
}

Status GltfImporter::ImportNodes(Asset* asset) const {
  const std::size_t count = model_.nodes.size();
  asset->nodes.resize(count);
  auto finite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  for (std::size_t i = 0; i < count; ++i) {
    const tinygltf::Node& node = model_.nodes[i];
    AssetNode& out = asset->nodes[i];
    const std::string np = Ptr("nodes", i);
    out.name = node.name;
    if (node.mesh >= 0 && static_cast<std::size_t>(node.mesh) >= model_.meshes.size()) {
      return Fail(np + "/mesh", "mesh " + Str(node.mesh) + " does not exist");
    }
    if (node.skin >= 0 && static_cast<std::size_t>(node.skin) >= model_.skins.size()) {
      return Fail(np + "/skin", "skin " + Str(node.skin) + " does not exist");
    }
    out.mesh = node.mesh;
    out.skin = node.skin;
    const struct {
      const char* name;
      const std::vector<double>* v;
      std::size_t size;
    } props[] = {{"matrix", &node.matrix, 16},
                 {"translation", &node.translation, 3},
                 {"rotation", &node.rotation, 4},
                 {"scale", &node.scale, 3},
                 {"weights", &node.weights, 0}};
    for (const auto& prop : props) {
      if (prop.size != 0 && !prop.v->empty() && prop.v->size() != prop.size) {
        return Fail(np + "/" + prop.name, "has " + Str(std::uint64_t{prop.v->size()}) +
                                              " numbers, expected " +
                                              Str(std::uint64_t{prop.size}));
      }
      if (!finite(*prop.v)) return Fail(np + "/" + prop.name, "contains NaN or infinity");
    }
    if (!node.matrix.empty()) {
      out.has_matrix = true;
      for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r)
          out.matrix[c][r] = node.matrix[static_cast<std::size_t>(c * 4 + r)];
      }
    }
    if (!node.translation.empty()) {
      out.translation = glm::dvec3(node.translation[0], node.translation[1], node.translation[2]);
    }
    if (!node.rotation.empty()) {
      out.rotation =
          glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
    }
    if (!node.scale.empty()) out.scale = glm::dvec3(node.scale[0], node.scale[1], node.scale[2]);
    out.weights = node.weights;
  }
  // Parents from children lists: each node has at most one parent and the graph has no cycle.
  for (std::size_t i = 0; i < count; ++i) {
    const std::vector<int>& children = model_.nodes[i].children;
    for (std::size_t k = 0; k < children.size(); ++k) {
      const std::string cp = Ptr("nodes", i) + Ptr("children", k);
      const int c = children[k];
      if (c < 0 || static_cast<std::size_t>(c) >= count) {
        return Fail(cp, "node " + Str(c) + " does not exist");
      }
      AssetNode& child = asset->nodes[static_cast<std::size_t>(c)];
      if (child.parent != kInvalidIndex) {
        return Fail(cp, "node " + Str(c) + " has two parents (" + Str(child.parent) + " and " +
                            Str(std::uint64_t{i}) + ")");
      }
      child.parent = static_cast<Index>(i);
      asset->nodes[i].children.push_back(c);
    }
  }
  // With one parent each, a cycle is a parent chain that comes back to where it started.
  std::vector<std::size_t> stamp(count, 0);  // 0: unvisited; otherwise the walk that saw it
  for (std::size_t i = 0; i < count; ++i) {
    std::size_t v = i;
    while (stamp[v] == 0) {
      stamp[v] = i + 1;
      if (asset->nodes[v].parent == kInvalidIndex) break;
      v = static_cast<std::size_t>(asset->nodes[v].parent);
    }
    if (stamp[v] == i + 1 && asset->nodes[v].parent != kInvalidIndex) {
      // v lies on a cycle: name the children entry that points at it.
      const std::size_t p = static_cast<std::size_t>(asset->nodes[v].parent);
      const std::vector<Index>& children = asset->nodes[p].children;
      const std::size_t k = static_cast<std::size_t>(
          std::find(children.begin(), children.end(), static_cast<Index>(v)) - children.begin());
      return Fail(Ptr("nodes", p) + Ptr("children", k),
                  "node " + Str(std::uint64_t{v}) + " is its own ancestor (cycle)");
    }
  }
  return Status::Ok();
}

Status GltfImporter::ImportSkins(Asset* asset) const {
  asset->skins.resize(model_.skins.size());
  for (std::size_t i = 0; i < model_.skins.size(); ++i) {
    const tinygltf::Skin& skin = model_.skins[i];
    AssetSkin& out = asset->skins[i];
    const std::string sp = Ptr("skins", i);
    out.name = skin.name;
    for (std::size_t k = 0; k < skin.joints.size(); ++k) {
      if (skin.joints[k] < 0 || static_cast<std::size_t>(skin.joints[k]) >= model_.nodes.size()) {
        return Fail(sp + Ptr("joints", k), "node " + Str(skin.joints[k]) + " does not exist");
      }
      out.joints.push_back(skin.joints[k]);
    }
    if (skin.skeleton >= 0 && static_cast<std::size_t>(skin.skeleton) >= model_.nodes.size()) {
      return Fail(sp + "/skeleton", "node " + Str(skin.skeleton) + " does not exist");
    }
    out.skeleton = skin.skeleton;
    const std::size_t n = skin.joints.size();
    out.inverse_bind_matrices.assign(n, glm::mat4(1.0f));
    out.has_inverse_bind_matrices = skin.inverseBindMatrices >= 0;
    if (!out.has_inverse_bind_matrices) continue;
    Decoded d;
    const std::string ip = sp + "/inverseBindMatrices";
    Status s = DecodeTyped(skin.inverseBindMatrices, ip, {TINYGLTF_TYPE_MAT4}, &d);
    if (!s.ok()) return s;
    if (d.count < n) {
      return Fail(ip, "accessor " + Str(skin.inverseBindMatrices) + " has " +
                          Str(std::uint64_t{d.count}) + " matrices for " + Str(std::uint64_t{n}) +
                          " joints");
    }
    for (std::size_t k = 0; k < n; ++k) {
      for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
          out.inverse_bind_matrices[k][c][r] =
              static_cast<float>(d.values[k * 16 + static_cast<std::size_t>(c * 4 + r)]);
        }
      }
    }
  }
  return Status::Ok();
}

// Linear in the file: the largest joint index of each mesh is found once, then compared with
// the joint count of every skinned node that uses the mesh (not one scan per node).
Status GltfImporter::CheckJointIndices(const Asset& asset) const {
  std::vector<std::size_t> max_joint(asset.meshes.size(), 0);
  std::vector<bool> has_joints(asset.meshes.size(), false);
  for (std::size_t m = 0; m < asset.meshes.size(); ++m) {
    for (const AssetPrimitive& prim : asset.meshes[m].primitives) {
      for (const auto& set : prim.joints) {
        for (const auto& j4 : set) {
          has_joints[m] = true;
          for (int c = 0; c < 4; ++c) max_joint[m] = std::max<std::size_t>(max_joint[m], j4[c]);
        }
      }
    }
  }
  for (std::size_t i = 0; i < asset.nodes.size(); ++i) {
    const AssetNode& node = asset.nodes[i];
    if (node.mesh < 0 || node.skin < 0) continue;
    const std::size_t m = static_cast<std::size_t>(node.mesh);
    const std::size_t joint_count = asset.skins[static_cast<std::size_t>(node.skin)].joints.size();
    if (!has_joints[m] || max_joint[m] < joint_count) continue;
    const AssetMesh& mesh = asset.meshes[m];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const AssetPrimitive& prim = mesh.primitives[p];
      for (std::size_t set = 0; set < prim.joints.size(); ++set) {
        for (std::size_t v = 0; v < prim.joints[set].size(); ++v) {
          for (int c = 0; c < 4; ++c) {
            const std::size_t j = prim.joints[set][v][c];
            if (j >= joint_count) {
              return Fail(Ptr("meshes", m) + Ptr("primitives", p) + "/attributes/JOINTS_" +
                              Str(std::uint64_t{set}),
                          "vertex " + Str(std::uint64_t{v}) + " has joint index " +
                              Str(std::uint64_t{j}) + " >= joint count " +
                              Str(std::uint64_t{joint_count}) + " of skin " + Str(node.skin) +
                              " (used by node " + Str(std::uint64_t{i}) + ")");
            }
          }
        }
      }
    }
  }
  return Status::Ok();
}

// The samplers of an animation: interpolation and key times; the outputs stay decoded until
// the channels say how many components they have.
Status GltfImporter::ImportSamplers(const tinygltf::Animation& anim, const std::string& ap,
                                    AssetAnimation* out, std::vector<Decoded>* outputs) const {
  out->samplers.resize(anim.samplers.size());
  outputs->resize(anim.samplers.size());
  for (std::size_t s = 0; s < anim.samplers.size(); ++s) {
    const tinygltf::AnimationSampler& in = anim.samplers[s];
    AssetAnimationSampler& sampler = out->samplers[s];
    const std::string sp = ap + Ptr("samplers", s);
    if (in.interpolation == "LINEAR") {
      sampler.interpolation = Interpolation::kLinear;
    } else if (in.interpolation == "STEP") {
      sampler.interpolation = Interpolation::kStep;
    } else if (in.interpolation == "CUBICSPLINE") {
      sampler.interpolation = Interpolation::kCubicSpline;
    } else {
      return Fail(sp + "/interpolation", "unknown interpolation '" + in.interpolation + "'");
    }
    Decoded times;
    Status st = DecodeTyped(in.input, sp + "/input", {TINYGLTF_TYPE_SCALAR}, &times);
    if (!st.ok()) return st;
    sampler.times.reserve(times.count);
    for (double t : times.values) sampler.times.push_back(static_cast<float>(t));
    st =
        DecodeTyped(in.output, sp + "/output",
                    {TINYGLTF_TYPE_SCALAR, TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4}, &(*outputs)[s]);
    if (!st.ok()) return st;
  }
  return Status::Ok();
}

// The channels of an animation, and the component count each sampler's output must have (the
// morph target count for weights); channels of extension paths or targets are skipped.
Status GltfImporter::ImportChannels(const tinygltf::Animation& anim, const std::string& ap,
                                    const std::vector<Decoded>& outputs, AssetAnimation* out,
                                    std::vector<int>* components) const {
  components->assign(anim.samplers.size(), 0);
  for (std::size_t c = 0; c < anim.channels.size(); ++c) {
    const tinygltf::AnimationChannel& in = anim.channels[c];
    const std::string cp = ap + Ptr("channels", c);
    if (in.sampler < 0 || static_cast<std::size_t>(in.sampler) >= anim.samplers.size()) {
      return Fail(cp + "/sampler", "sampler " + Str(in.sampler) + " does not exist");
    }
    if (in.target_node < 0) continue;  // animates something an extension defines: skipped
    if (static_cast<std::size_t>(in.target_node) >= model_.nodes.size()) {
      return Fail(cp + "/target/node", "node " + Str(in.target_node) + " does not exist");
    }
    AssetAnimationChannel channel;
    channel.sampler = in.sampler;
    channel.node = in.target_node;
    int k = 0;
    const std::size_t s = static_cast<std::size_t>(in.sampler);
    const Decoded& values = outputs[s];
    if (in.target_path == "translation" || in.target_path == "scale") {
      channel.path =
          in.target_path == "scale" ? AnimationPath::kScale : AnimationPath::kTranslation;
      k = 3;
    } else if (in.target_path == "rotation") {
      channel.path = AnimationPath::kRotation;
      k = 4;
    } else if (in.target_path == "weights") {
      channel.path = AnimationPath::kWeights;
      const tinygltf::Node& node = model_.nodes[static_cast<std::size_t>(in.target_node)];
      if (node.mesh >= 0 &&
          !model_.meshes[static_cast<std::size_t>(node.mesh)].primitives.empty()) {
        k = static_cast<int>(
            model_.meshes[static_cast<std::size_t>(node.mesh)].primitives[0].targets.size());
      } else {
        const std::size_t per_key =
            out->samplers[s].times.size() *
            (out->samplers[s].interpolation == Interpolation::kCubicSpline ? 3 : 1);
        k = per_key == 0 ? 0 : static_cast<int>(values.values.size() / per_key);
      }
    } else {
      continue;  // a path of an extension (e.g. KHR_animation_pointer): skipped
    }
    if (static_cast<std::size_t>(k) != values.components &&
        channel.path != AnimationPath::kWeights) {
      return Fail(ap + Ptr("samplers", s) + "/output", "accessor " + Str(anim.samplers[s].output) +
                                                           " has type " + TypeName(values.type) +
                                                           ", channel " + Str(std::uint64_t{c}) +
                                                           " animates " + in.target_path);
    }
    if ((*components)[s] != 0 && (*components)[s] != k) {
      return Fail(cp + "/sampler", "sampler " + Str(in.sampler) + " is shared by channels with " +
                                       Str((*components)[s]) + " and " + Str(k) + " components");
    }
    (*components)[s] = k;
    out->channels.push_back(channel);
  }
  return Status::Ok();
}

// Each sampler's output values, checked against its key count and component count (taken
// from the output type for a sampler no channel uses).
Status GltfImporter::SetSamplerValues(const std::string& ap, const std::vector<Decoded>& outputs,
                                      std::vector<int>* components, AssetAnimation* out) const {
  for (std::size_t s = 0; s < out->samplers.size(); ++s) {
    AssetAnimationSampler& sampler = out->samplers[s];
    const Decoded& values = outputs[s];
    int& k = (*components)[s];
    const std::size_t mult = sampler.interpolation == Interpolation::kCubicSpline ? 3 : 1;
    if (k == 0) {  // unused by any channel: from the output type
      k = values.type == TINYGLTF_TYPE_SCALAR && !sampler.times.empty()
              ? static_cast<int>(values.values.size() / (sampler.times.size() * mult))
              : static_cast<int>(values.components);
    }
    sampler.components = k;
    const std::uint64_t expected =
        std::uint64_t{sampler.times.size()} * mult * static_cast<std::uint64_t>(k);
    if (values.values.size() != expected) {
      return Fail(ap + Ptr("samplers", s) + "/output",
                  Str(std::uint64_t{values.values.size()}) + " values, expected " + Str(expected) +
                      " (" + Str(std::uint64_t{sampler.times.size()}) + " keyframes x " + Str(k) +
                      " components" + (mult == 3 ? " x 3 for CUBICSPLINE)" : ")"));
    }
    sampler.values.reserve(values.values.size());
    for (double v : values.values) sampler.values.push_back(static_cast<float>(v));
  }
  return Status::Ok();
}

Status GltfImporter::ImportAnimations(Asset* asset) const {
  asset->animations.resize(model_.animations.size());
  for (std::size_t a = 0; a < model_.animations.size(); ++a) {
    const tinygltf::Animation& anim = model_.animations[a];
    AssetAnimation& out = asset->animations[a];
    const std::string ap = Ptr("animations", a);
    out.name = anim.name;
    std::vector<Decoded> outputs;
    Status s = ImportSamplers(anim, ap, &out, &outputs);
    std::vector<int> components;
    if (s.ok()) s = ImportChannels(anim, ap, outputs, &out, &components);
    if (s.ok()) s = SetSamplerValues(ap, outputs, &components, &out);
    if (!s.ok()) return s;
  }
  return Status::Ok();
}

Status GltfImporter::ImportDsurf(std::string* bytes) const {
  bytes->clear();
  auto ext = doc_.find("extensions");
  if (ext == doc_.end() || !ext->is_object()) return Status::Ok();
  auto dsurf = ext->find(kDsurfGltfExtension);
  if (dsurf == ext->end()) return Status::Ok();
  const std::string pointer = std::string("/extensions/") + kDsurfGltfExtension + "/bufferView";
  if (!dsurf->is_object() || !dsurf->contains("bufferView") ||
      !dsurf->at("bufferView").is_number_integer()) {
    return Fail(pointer, "missing or not an integer");
  }
  const Json& index = dsurf->at("bufferView");
  const std::int64_t view = index.get<std::int64_t>();
  if (view < 0 || static_cast<std::uint64_t>(view) >= model_.bufferViews.size()) {
    return Fail(pointer, "bufferView " + std::to_string(view) + " does not exist");
  }
  const unsigned char* data = nullptr;
  std::size_t size = 0;
  Status s = View(static_cast<int>(view), pointer, &data, &size);
  if (!s.ok()) return s;
  bytes->assign(reinterpret_cast<const char*>(data), size);
  return Status::Ok();
}

Status GltfImporter::Run(Asset* out, std::string* dsurf_bytes) {
  Status s = Load();
  if (!s.ok()) return s;
  Asset asset;
  asset.source = path_;
  asset.generator = model_.asset.generator;
  asset.copyright = model_.asset.copyright;
  if (!(s = ImportMeshes(&asset)).ok()) return s;
  if (!(s = ImportMaterials(&asset)).ok()) return s;
  if (!(s = ImportImages(&asset)).ok()) return s;
  if (!(s = ImportNodes(&asset)).ok()) return s;
  if (!(s = ImportSkins(&asset)).ok()) return s;
  if (!(s = CheckJointIndices(asset)).ok()) return s;
  if (!(s = ImportAnimations(&asset)).ok()) return s;
  asset.scenes.resize(model_.scenes.size());
  for (std::size_t i = 0; i < model_.scenes.size(); ++i) {
    asset.scenes[i].name = model_.scenes[i].name;
    asset.scenes[i].nodes.assign(model_.scenes[i].nodes.begin(), model_.scenes[i].nodes.end());
  }
  if (model_.defaultScene >= 0 &&
      static_cast<std::size_t>(model_.defaultScene) >= model_.scenes.size()) {
    return Fail("/scene", "scene " + Str(model_.defaultScene) + " does not exist");
  }
  asset.default_scene = model_.defaultScene;
  if (dsurf_bytes != nullptr && !(s = ImportDsurf(dsurf_bytes)).ok()) return s;
  if (!(s = ValidateAsset(asset)).ok()) return s;
  *out = std::move(asset);
  return Status::Ok();
}

}  // namespace

Status ImportGltf(const std::string& path, Asset* out, std::string* dsurf_bytes) {
  if (out == nullptr) return Status::InvalidInput(path + ": ImportGltf: null output asset");
  if (dsurf_bytes != nullptr) dsurf_bytes->clear();
  try {
    GltfImporter importer(path);
    return importer.Run(out, dsurf_bytes);
  } catch (const std::bad_alloc&) {
    return Status::Internal(path + ": out of memory while importing");
  } catch (const std::exception& e) {
    return Status::Internal(path + ": " + e.what());
  }
}

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Binary layout: docs/asset-stream.md.
#include "dermis/asset/asset_io.h"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "core/byte_stream.h"
#include "dermis/asset/asset_validate.h"

namespace dermis {
namespace {

constexpr char kMagic[8] = {'D', 'A', 'S', 'S', 'E', 'T', '\0', '\0'};

// Smallest encoded size of each element kind, used to bound counts before allocating.
constexpr std::uint64_t kMinString = 8;
constexpr std::uint64_t kMinArray = 8;
constexpr std::uint64_t kMinMesh = kMinString + 2 * kMinArray;
constexpr std::uint64_t kMinPrimitive = 1 + 4 + 9 * kMinArray;
constexpr std::uint64_t kMinTarget = 3 * kMinArray;
constexpr std::uint64_t kMinMaterial = 2 * kMinString;
constexpr std::uint64_t kMinTexture = kMinString + 2 * 4;
constexpr std::uint64_t kMinImage = 3 * kMinString;
constexpr std::uint64_t kMinSampler = kMinString + 4 * 4;
constexpr std::uint64_t kMinNode =
    kMinString + 4 + kMinArray + 3 * 8 + 4 * 8 + 3 * 8 + 1 + 16 * 8 + 4 + 4 + kMinArray;
constexpr std::uint64_t kMinSkin = kMinString + 2 * kMinArray + 1 + 4;
constexpr std::uint64_t kMinAnimation = kMinString + 2 * kMinArray;
constexpr std::uint64_t kMinAnimSampler = 2 * kMinArray + 4 + 1;
constexpr std::uint64_t kMinChannel = 4 + 4 + 1;
constexpr std::uint64_t kMinScene = kMinString + kMinArray;

// ---------------------------------------------------------------------------------------------
// Writing.

/// The shared little-endian writer (core/byte_stream.h) plus the asset stream's compound
/// encodings: booleans, counts, GLM vectors, arrays and arrays of sets.
class Writer : public ByteWriter {
 public:
  void Bool(bool v) { U8(v ? 1 : 0); }
  void Count(std::size_t n) { U64(static_cast<std::uint64_t>(n)); }
  void Vec(const glm::vec2& v) {
    F32(v.x);
    F32(v.y);
  }
  void Vec(const glm::vec3& v) {
    F32(v.x);
    F32(v.y);
    F32(v.z);
  }
  void Vec(const glm::vec4& v) {
    F32(v.x);
    F32(v.y);
    F32(v.z);
    F32(v.w);
  }
  void Vec(const glm::u16vec4& v) {
    for (int i = 0; i < 4; ++i) U16(v[i]);
  }
  void Vec(const glm::dvec3& v) {
    F64(v.x);
    F64(v.y);
    F64(v.z);
  }
  void Elem(float v) { F32(v); }
  void Elem(double v) { F64(v); }
  void Elem(std::int32_t v) { I32(v); }
  void Elem(std::uint32_t v) { U32(v); }
  template <typename T>
  void Elem(const T& v) {
    Vec(v);
  }
  template <typename T>
  void Array(const std::vector<T>& values) {
    Count(values.size());
    for (const T& v : values) Elem(v);
  }
  template <typename T>
  void Sets(const std::vector<std::vector<T>>& sets) {
    Count(sets.size());
    for (const std::vector<T>& s : sets) Array(s);
  }

  std::string Take() { return std::move(str()); }
};

void WritePrimitive(Writer& w, const AssetPrimitive& p) {
  w.U8(static_cast<std::uint8_t>(p.mode));
  w.I32(p.material);
  w.Array(p.positions);
  w.Array(p.normals);
  w.Array(p.tangents);
  w.Sets(p.texcoords);
  w.Sets(p.colors);
  w.Sets(p.joints);
  w.Sets(p.weights);
  w.Array(p.indices);
  w.Count(p.targets.size());
  for (const AssetMorphTarget& t : p.targets) {
    w.Array(t.positions);
    w.Array(t.normals);
    w.Array(t.tangents);
  }
}

void WriteNode(Writer& w, const AssetNode& n) {
  w.Str(n.name);
  w.I32(n.parent);
  w.Array(n.children);
  w.Vec(n.translation);
  w.F64(n.rotation.x);
  w.F64(n.rotation.y);
  w.F64(n.rotation.z);
  w.F64(n.rotation.w);
  w.Vec(n.scale);
  w.Bool(n.has_matrix);
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) w.F64(n.matrix[c][r]);
  }
  w.I32(n.mesh);
  w.I32(n.skin);
  w.Array(n.weights);
}

void WriteSkin(Writer& w, const AssetSkin& s) {
  w.Str(s.name);
  w.Array(s.joints);
  w.Count(s.inverse_bind_matrices.size());
  for (const glm::mat4& m : s.inverse_bind_matrices) {
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) w.F32(m[c][r]);
    }
  }
  w.Bool(s.has_inverse_bind_matrices);
  w.I32(s.skeleton);
}

void WriteAnimation(Writer& w, const AssetAnimation& a) {
  w.Str(a.name);
  w.Count(a.samplers.size());
  for (const AssetAnimationSampler& s : a.samplers) {
    w.Array(s.times);
    w.Array(s.values);
    w.I32(s.components);
    w.U8(static_cast<std::uint8_t>(s.interpolation));
  }
  w.Count(a.channels.size());
  for (const AssetAnimationChannel& c : a.channels) {
    w.I32(c.sampler);
    w.I32(c.node);
    w.U8(static_cast<std::uint8_t>(c.path));
  }
}

// ---------------------------------------------------------------------------------------------
// Reading.

/// Reads little-endian fields; the first failure is kept with the path to the field.
class Reader {
 public:
  Reader(std::string_view bytes, const std::string& name) : bytes_(bytes), name_(name) {}

  bool ok() const { return error_.empty(); }
  const std::string& error() const { return error_; }
  std::uint64_t remaining() const { return bytes_.size() - pos_; }

  /// A path element such as "meshes[2]" or "positions"; index < 0 means no index.
  void Push(const char* field, std::int64_t index = -1) { path_.push_back({field, index}); }
  void Pop() { path_.pop_back(); }

  bool Fail(const std::string& what) {
    if (!error_.empty()) return false;
    std::string path;
    for (const PathPart& part : path_) {
      if (!path.empty()) path += ".";
      path += part.field;
      if (part.index >= 0) path += "[" + std::to_string(part.index) + "]";
    }
    error_ = name_ + ": asset stream: " + (path.empty() ? "header" : path) + ": " + what;
    return false;
  }

  bool Raw(void* dst, std::size_t n) {
    if (!ok()) return false;
    if (remaining() < n) return Fail("unexpected end of data");
    if (n > 0) std::memcpy(dst, bytes_.data() + pos_, n);
    pos_ += n;
    return true;
  }
  bool U8(std::uint8_t* v) { return Raw(v, 1); }
  bool U16(std::uint16_t* v) {
    unsigned char b[2] = {};
    if (!Raw(b, 2)) return false;
    *v = static_cast<std::uint16_t>(b[0] | (b[1] << 8));
    return true;
  }
  bool U32(std::uint32_t* v) {
    unsigned char b[4] = {};
    if (!Raw(b, 4)) return false;
    *v = 0;
    for (int i = 3; i >= 0; --i) *v = (*v << 8) | b[i];
    return true;
  }
  bool U64(std::uint64_t* v) {
    unsigned char b[8] = {};
    if (!Raw(b, 8)) return false;
    *v = 0;
    for (int i = 7; i >= 0; --i) *v = (*v << 8) | b[i];
    return true;
  }
  bool I32(std::int32_t* v) {
    std::uint32_t u;
    if (!U32(&u)) return false;
    std::memcpy(v, &u, 4);
    return true;
  }
  bool F32(float* v) {
    std::uint32_t u;
    if (!U32(&u)) return false;
    std::memcpy(v, &u, 4);
    return true;
  }
  bool F64(double* v) {
    std::uint64_t u;
    if (!U64(&u)) return false;
    std::memcpy(v, &u, 8);
    return true;
  }
  bool Bool(bool* v) {
    std::uint8_t b = 0;
    if (!U8(&b)) return false;
    if (b > 1) return Fail("boolean byte " + std::to_string(b) + " is not 0 or 1");
    *v = b == 1;
    return true;
  }
  /// Reads a count and checks that `count * min_size` bytes remain, before any allocation.
  bool Count(std::uint64_t min_size, std::size_t* count) {
    std::uint64_t n = 0;
    if (!U64(&n)) return false;
    if (n > remaining() / min_size) return Fail("count exceeds data");
    *count = static_cast<std::size_t>(n);
    return true;
  }
  bool Str(const char* field, std::string* s) {
    Push(field);
    std::size_t n = 0;
    if (Count(1, &n)) {
      s->assign(bytes_.data() + pos_, n);
      pos_ += n;
    }
    Pop();
    return ok();
  }
  bool Vec(glm::vec2* v) { return F32(&v->x) && F32(&v->y); }
  bool Vec(glm::vec3* v) { return F32(&v->x) && F32(&v->y) && F32(&v->z); }
  bool Vec(glm::vec4* v) { return F32(&v->x) && F32(&v->y) && F32(&v->z) && F32(&v->w); }
  bool Vec(glm::u16vec4* v) { return U16(&v->x) && U16(&v->y) && U16(&v->z) && U16(&v->w); }
  bool Vec(glm::dvec3* v) { return F64(&v->x) && F64(&v->y) && F64(&v->z); }
  bool Elem(float* v) { return F32(v); }
  bool Elem(double* v) { return F64(v); }
  bool Elem(std::int32_t* v) { return I32(v); }
  bool Elem(std::uint32_t* v) { return U32(v); }
  template <typename T>
  bool Elem(T* v) {
    return Vec(v);
  }
  /// An array of fixed-size elements of `size` bytes each.
  template <typename T>
  bool Array(const char* field, std::uint64_t size, std::vector<T>* values,
             std::int64_t index = -1) {
    Push(field, index);
    std::size_t n = 0;
    if (Count(size, &n)) {
      values->resize(n);
      for (std::size_t i = 0; i < n && Elem(&(*values)[i]); ++i) {
      }
    }
    Pop();
    return ok();
  }
  template <typename T>
  bool Sets(const char* field, std::uint64_t size, std::vector<std::vector<T>>* sets) {
    Push(field);
    std::size_t n = 0;
    if (Count(kMinArray, &n)) {
      Pop();
      sets->resize(n);
      for (std::size_t i = 0; i < n && Array(field, size, &(*sets)[i], std::int64_t(i)); ++i) {
      }
      return ok();
    }
    Pop();
    return false;
  }
  /// Reads an enum byte and checks it is <= `max`.
  template <typename E>
  bool Enum(const char* field, std::uint8_t max, E* e) {
    Push(field);
    std::uint8_t b = 0;
    if (U8(&b)) {
      if (b > max) {
        Fail("value " + std::to_string(b) + " out of range");
      } else {
        *e = static_cast<E>(b);
      }
    }
    Pop();
    return ok();
  }
  bool AtEnd() const { return pos_ == bytes_.size(); }

 private:
  struct PathPart {
    const char* field;
    std::int64_t index;
  };
  std::string_view bytes_;
  const std::string& name_;
  std::size_t pos_ = 0;
  std::vector<PathPart> path_;
  std::string error_;
};

/// Pushes "field[i]" for the duration of a scope.
class Scope {
 public:
  Scope(Reader& r, const char* field, std::size_t index = static_cast<std::size_t>(-1)) : r_(r) {
    r_.Push(field, index == static_cast<std::size_t>(-1) ? -1 : std::int64_t(index));
  }
  ~Scope() { r_.Pop(); }
  Scope(const Scope&) = delete;
  Scope& operator=(const Scope&) = delete;

 private:
  Reader& r_;
};

bool ReadPrimitive(Reader& r, AssetPrimitive* p) {
  if (!r.Enum("mode", static_cast<std::uint8_t>(PrimitiveMode::kTriangleFan), &p->mode)) {
    return false;
  }
  {
    Scope s(r, "material");
    if (!r.I32(&p->material)) return false;
  }
  if (!r.Array("positions", 12, &p->positions) || !r.Array("normals", 12, &p->normals) ||
      !r.Array("tangents", 16, &p->tangents) || !r.Sets("texcoords", 8, &p->texcoords) ||
      !r.Sets("colors", 16, &p->colors) || !r.Sets("joints", 8, &p->joints) ||
      !r.Sets("weights", 16, &p->weights) || !r.Array("indices", 4, &p->indices)) {
    return false;
  }
  std::size_t n = 0;
  {
    Scope s(r, "targets");
    if (!r.Count(kMinTarget, &n)) return false;
  }
  p->targets.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    Scope s(r, "targets", t);
    AssetMorphTarget& target = p->targets[t];
    if (!r.Array("positions", 12, &target.positions) || !r.Array("normals", 12, &target.normals) ||
        !r.Array("tangents", 12, &target.tangents)) {
      return false;
    }
  }
  return true;
}

bool ReadMesh(Reader& r, AssetMesh* m) {
  if (!r.Str("name", &m->name)) return false;
  std::size_t n = 0;
  {
    Scope s(r, "primitives");
    if (!r.Count(kMinPrimitive, &n)) return false;
  }
  m->primitives.resize(n);
  for (std::size_t p = 0; p < n; ++p) {
    Scope s(r, "primitives", p);
    if (!ReadPrimitive(r, &m->primitives[p])) return false;
  }
  return r.Array("weights", 4, &m->weights);
}

bool ReadNode(Reader& r, AssetNode* n) {
  if (!r.Str("name", &n->name)) return false;
  {
    Scope s(r, "parent");
    if (!r.I32(&n->parent)) return false;
  }
  if (!r.Array("children", 4, &n->children)) return false;
  {
    Scope s(r, "trs");
    double q[4];
    if (!r.Vec(&n->translation) || !r.F64(&q[0]) || !r.F64(&q[1]) || !r.F64(&q[2]) ||
        !r.F64(&q[3]) || !r.Vec(&n->scale)) {
      return false;
    }
    n->rotation = glm::dquat(q[3], q[0], q[1], q[2]);
  }
  {
    Scope s(r, "matrix");
    if (!r.Bool(&n->has_matrix)) return false;
    for (int c = 0; c < 4; ++c) {
      for (int row = 0; row < 4; ++row) {
        if (!r.F64(&n->matrix[c][row])) return false;
      }
    }
  }
  {
    Scope s(r, "mesh");
    if (!r.I32(&n->mesh)) return false;
  }
  {
    Scope s(r, "skin");
    if (!r.I32(&n->skin)) return false;
  }
  return r.Array("weights", 8, &n->weights);
}

bool ReadSkin(Reader& r, AssetSkin* s) {
  if (!r.Str("name", &s->name) || !r.Array("joints", 4, &s->joints)) return false;
  {
    Scope scope(r, "inverse_bind_matrices");
    std::size_t n = 0;
    if (!r.Count(64, &n)) return false;
    s->inverse_bind_matrices.resize(n);
    for (glm::mat4& m : s->inverse_bind_matrices) {
      for (int c = 0; c < 4; ++c) {
        for (int row = 0; row < 4; ++row) {
          if (!r.F32(&m[c][row])) return false;
        }
      }
    }
  }
  Scope scope(r, "skeleton");
  return r.Bool(&s->has_inverse_bind_matrices) && r.I32(&s->skeleton);
}

bool ReadAnimation(Reader& r, AssetAnimation* a) {
  if (!r.Str("name", &a->name)) return false;
  std::size_t n = 0;
  {
    Scope s(r, "samplers");
    if (!r.Count(kMinAnimSampler, &n)) return false;
  }
  a->samplers.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    Scope s(r, "samplers", k);
    AssetAnimationSampler& sampler = a->samplers[k];
    if (!r.Array("times", 4, &sampler.times) || !r.Array("values", 4, &sampler.values)) {
      return false;
    }
    {
      Scope c(r, "components");
      if (!r.I32(&sampler.components)) return false;
    }
    if (!r.Enum("interpolation", static_cast<std::uint8_t>(Interpolation::kCubicSpline),
                &sampler.interpolation)) {
      return false;
    }
  }
  {
    Scope s(r, "channels");
    if (!r.Count(kMinChannel, &n)) return false;
  }
  a->channels.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    Scope s(r, "channels", k);
    AssetAnimationChannel& c = a->channels[k];
    if (!r.I32(&c.sampler) || !r.I32(&c.node) ||
        !r.Enum("path", static_cast<std::uint8_t>(AnimationPath::kWeights), &c.path)) {
      return false;
    }
  }
  return true;
}

/// Reads a section: a count of elements of at least `min_size` bytes, then each element.
template <typename T, typename F>
bool ReadSection(Reader& r, const char* field, std::uint64_t min_size, std::vector<T>* out,
                 F read) {
  std::size_t n = 0;
  {
    Scope s(r, field);
    if (!r.Count(min_size, &n)) return false;
  }
  out->resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    Scope s(r, field, i);
    if (!read(r, &(*out)[i])) return false;
  }
  return true;
}

}  // namespace

std::string SerializeAsset(const Asset& asset) {
  Writer w;
  for (char c : kMagic) w.U8(static_cast<std::uint8_t>(c));
  w.U32(kAssetStreamVersion);
  w.Str(asset.generator);
  w.Str(asset.copyright);
  w.I32(asset.default_scene);
  w.Count(asset.meshes.size());
  for (const AssetMesh& m : asset.meshes) {
    w.Str(m.name);
    w.Count(m.primitives.size());
    for (const AssetPrimitive& p : m.primitives) WritePrimitive(w, p);
    w.Array(m.weights);
  }
  w.Count(asset.materials.size());
  for (const AssetMaterial& m : asset.materials) {
    w.Str(m.name);
    w.Str(m.json);
  }
  w.Count(asset.textures.size());
  for (const AssetTexture& t : asset.textures) {
    w.Str(t.name);
    w.I32(t.image);
    w.I32(t.sampler);
  }
  w.Count(asset.images.size());
  for (const AssetImage& i : asset.images) {
    w.Str(i.name);
    w.Str(i.mime_type);
    w.Str(i.bytes);
  }
  w.Count(asset.samplers.size());
  for (const AssetSampler& s : asset.samplers) {
    w.Str(s.name);
    w.I32(s.mag_filter);
    w.I32(s.min_filter);
    w.I32(s.wrap_s);
    w.I32(s.wrap_t);
  }
  w.Count(asset.nodes.size());
  for (const AssetNode& n : asset.nodes) WriteNode(w, n);
  w.Count(asset.skins.size());
  for (const AssetSkin& s : asset.skins) WriteSkin(w, s);
  w.Count(asset.animations.size());
  for (const AssetAnimation& a : asset.animations) WriteAnimation(w, a);
  w.Count(asset.scenes.size());
  for (const AssetScene& s : asset.scenes) {
    w.Str(s.name);
    w.Array(s.nodes);
  }
  return w.Take();
}

Status ParseAsset(std::string_view bytes, const std::string& name, Asset* out) {
  Reader r(bytes, name);
  Asset asset;
  asset.source = name;
  char magic[8];
  std::uint32_t version = 0;
  if (!r.Raw(magic, 8)) return Status::InvalidInput(r.error());
  if (std::memcmp(magic, kMagic, 8) != 0) {
    r.Fail("bad magic (not an asset stream)");
    return Status::InvalidInput(r.error());
  }
  if (!r.U32(&version)) return Status::InvalidInput(r.error());
  if (version != kAssetStreamVersion) {
    r.Fail("unsupported version " + std::to_string(version));
    return Status::Unsupported(r.error());
  }
  bool good = r.Str("generator", &asset.generator) && r.Str("copyright", &asset.copyright);
  if (good) {
    Scope s(r, "default_scene");
    good = r.I32(&asset.default_scene);
  }
  good = good && ReadSection(r, "meshes", kMinMesh, &asset.meshes, ReadMesh) &&
         ReadSection(r, "materials", kMinMaterial, &asset.materials,
                     [](Reader& rd, AssetMaterial* m) {
                       return rd.Str("name", &m->name) && rd.Str("json", &m->json);
                     }) &&
         ReadSection(r, "textures", kMinTexture, &asset.textures,
                     [](Reader& rd, AssetTexture* t) {
                       return rd.Str("name", &t->name) && rd.I32(&t->image) && rd.I32(&t->sampler);
                     }) &&
         ReadSection(r, "images", kMinImage, &asset.images,
                     [](Reader& rd, AssetImage* i) {
                       return rd.Str("name", &i->name) && rd.Str("mime_type", &i->mime_type) &&
                              rd.Str("bytes", &i->bytes);
                     }) &&
         ReadSection(r, "samplers", kMinSampler, &asset.samplers,
                     [](Reader& rd, AssetSampler* s) {
                       return rd.Str("name", &s->name) && rd.I32(&s->mag_filter) &&
                              rd.I32(&s->min_filter) && rd.I32(&s->wrap_s) && rd.I32(&s->wrap_t);
                     }) &&
         ReadSection(r, "nodes", kMinNode, &asset.nodes, ReadNode) &&
         ReadSection(r, "skins", kMinSkin, &asset.skins, ReadSkin) &&
         ReadSection(r, "animations", kMinAnimation, &asset.animations, ReadAnimation) &&
         ReadSection(r, "scenes", kMinScene, &asset.scenes, [](Reader& rd, AssetScene* s) {
           return rd.Str("name", &s->name) && rd.Array("nodes", 4, &s->nodes);
         });
  if (!good) return Status::InvalidInput(r.error());
  if (!r.AtEnd()) {
    Scope s(r, "end");
    r.Fail(std::to_string(r.remaining()) + " trailing bytes after the asset");
    return Status::InvalidInput(r.error());
  }
  Status status = ValidateAsset(asset);
  if (!status.ok()) return status;
  *out = std::move(asset);
  return Status::Ok();
}

}  // namespace dermis

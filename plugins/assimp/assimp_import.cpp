// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Import of every non-glTF format Assimp 5.2 reads into the neutral asset module.
//
// Mapping (documented here because the asset module is glTF-shaped and Assimp is not):
// - Post-processing: Triangulate (polygons -> triangles; points and lines stay),
//   JoinIdenticalVertices (Assimp's importers emit one vertex per face corner; joining keeps
//   the first of each group of identical vertices, in order, and remaps the bone weights),
//   FlipUVs (UVs use glTF's convention: v = 0 is the top of the image), ValidateDataStructure.
//   No flag that splits, sorts or limits bone weights, so every influence survives.
// - Nodes: the aiNode tree in depth-first order (node 0 is Assimp's root, the only root of the
//   one scene). A local matrix becomes TRS when T * R * S reproduces it within 1e-6 relative,
//   else it stays a matrix. A node drawing one aiMesh gets it (and its skin) directly; a node
//   drawing k > 1 aiMeshes gets k extra children "<name>#<i>" with identity transforms, one per
//   aiMesh, appended after the depth-first nodes.
// - Meshes: one AssetMesh per aiMesh. Its faces are grouped by size into a triangle, a line
//   and a point primitive (in that order, only those present). A mesh with one kind of face
//   keeps its vertex array as is; otherwise each primitive keeps the vertices its faces use, in
//   their original order. A mesh without faces becomes one unindexed point primitive.
// - Skins: one per aiMesh with bones. Joints are the nodes named like the bones (first in
//   depth-first order), inverse bind matrices the bone offset matrices. Influences per vertex
//   are sorted by weight (descending, ties by joint), packed in JOINTS_n/WEIGHTS_n sets of 4
//   (as many sets as the most influenced vertex needs) and renormalised to sum 1.
// - Materials: glTF-like JSON {name, pbrMetallicRoughness{baseColorFactor, metallicFactor,
//   roughnessFactor, baseColorTexture?}, alphaMode?, doubleSided?}. The base colour comes from
//   $clr.base or else the diffuse colour, alpha from the opacity.
// - Images: embedded compressed textures (aiTexture::mHeight == 0) keep their bytes with a mime
//   type from achFormatHint; uncompressed embedded texel arrays are skipped. A diffuse / base
//   colour texture that names a file next to the model is read from disk.
// - Animations: T/R/S samplers, LINEAR, times = mTime / mTicksPerSecond (25 if 0); keys whose
//   time does not increase are dropped. Morph (mesh) animations are not imported.
#include <assimp/commonMetaData.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <iterator>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "dermis/asset/asset_validate.h"
#include "dermis/core/file_io.h"
#include "dermis/core/limits.h"
#include "dermis/core/path.h"
#include "dermis/plugins/assimp.h"

namespace dermis {
namespace {

std::string JsonString(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (u < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof(buf), "\\u%04x", static_cast<unsigned>(u));
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string JsonNumber(double v) {
  if (!std::isfinite(v)) v = 0.0;
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.9g", v);
  return buf;
}

glm::dmat4 ToGlm(const aiMatrix4x4& m) {
  // aiMatrix4x4 is row-major (a1..a4 is the first row); glm is column-major: m[column][row].
  const ai_real* r = &m.a1;
  glm::dmat4 g(1.0);
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) g[col][row] = static_cast<double>(r[row * 4 + col]);
  return g;
}

/// Splits `m` into TRS when T * R * S gives it back within 1e-6 relative.
void SetNodeTransform(const glm::dmat4& m, AssetNode* node) {
  node->has_matrix = true;
  node->matrix = m;
  double largest = 1.0;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) largest = std::max(largest, std::abs(m[c][r]));
  if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0) return;
  glm::dvec3 scale(glm::length(glm::dvec3(m[0])), glm::length(glm::dvec3(m[1])),
                   glm::length(glm::dvec3(m[2])));
  if (!(scale.x > 0.0 && scale.y > 0.0 && scale.z > 0.0)) return;
  if (glm::determinant(glm::dmat3(m)) < 0.0) scale.x = -scale.x;
  const glm::dvec3 c0 = glm::dvec3(m[0]) / scale.x;
  const glm::dvec3 c1 = glm::dvec3(m[1]) / scale.y;
  const glm::dvec3 c2 = glm::dvec3(m[2]) / scale.z;
  const glm::dmat3 rot(c0, c1, c2);
  glm::dquat q = glm::normalize(glm::quat_cast(rot));
  const glm::dvec3 t(m[3]);
  glm::dmat4 back = glm::mat4_cast(q);
  back[0] *= scale.x;
  back[1] *= scale.y;
  back[2] *= scale.z;
  back[3] = glm::dvec4(t, 1.0);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!(std::abs(back[c][r] - m[c][r]) <= 1e-6 * largest)) return;
  node->has_matrix = false;
  node->matrix = glm::dmat4(1.0);
  node->translation = t;
  node->rotation = q;
  node->scale = scale;
}

std::string MimeFromHint(const std::string& hint_in) {
  std::string hint = AsciiLower(hint_in);
  if (!hint.empty() && hint[0] == '.') hint.erase(0, 1);
  if (hint == "png") return "image/png";
  if (hint == "jpg" || hint == "jpeg") return "image/jpeg";
  if (hint == "ktx2") return "image/ktx2";
  if (hint == "webp") return "image/webp";
  if (hint == "bmp") return "image/bmp";
  if (hint == "gif") return "image/gif";
  if (hint == "tga") return "image/x-tga";
  if (hint == "dds") return "image/vnd-ms.dds";
  return {};
}

glm::vec3 UnitOr(const aiVector3D& v, const glm::vec3& fallback) {
  const glm::vec3 g(v.x, v.y, v.z);
  const float len = glm::length(g);
  if (!(len > 0.0f) || !std::isfinite(len)) return fallback;
  return g / len;
}

class Converter {
 public:
  Converter(const aiScene& scene, const std::string& path, Asset* out)
      : scene_(scene), path_(path), out_(out) {}

  Status Run() {
    out_->source = path_;
    ReadMetadata();
    AddNode(*scene_.mRootNode, kInvalidIndex);
    Status s = ConvertTextures();
    if (!s.ok()) return s;
    ConvertMaterials();
    mesh_skin_.assign(scene_.mNumMeshes, kInvalidIndex);
    for (unsigned i = 0; i < scene_.mNumMeshes; ++i) {
      if (!(s = ConvertMesh(i)).ok()) return s;
    }
    AttachMeshes();
    for (unsigned i = 0; i < scene_.mNumAnimations; ++i) {
      if (!(s = ConvertAnimation(i)).ok()) return s;
    }
    AssetScene asset_scene;
    asset_scene.name = scene_.mRootNode->mName.C_Str();
    asset_scene.nodes.push_back(0);
    out_->scenes.push_back(asset_scene);
    out_->default_scene = 0;
    return Status::Ok();
  }

 private:
  Status Error(const std::string& where, const std::string& what) const {
    return Status::InvalidInput(path_ + ": " + where + ": " + what);
  }

  void ReadMetadata() {
    if (scene_.mMetaData == nullptr) return;
    aiString value;
    if (scene_.mMetaData->Get(AI_METADATA_SOURCE_GENERATOR, value)) out_->generator = value.C_Str();
    if (scene_.mMetaData->Get(AI_METADATA_SOURCE_COPYRIGHT, value)) out_->copyright = value.C_Str();
  }

  // Depth-first: a node, then its subtrees in order.
  Index AddNode(const aiNode& ai, Index parent) {
    const auto index = static_cast<Index>(out_->nodes.size());
    out_->nodes.emplace_back();
    ai_nodes_.push_back(&ai);
    {
      AssetNode& node = out_->nodes.back();
      node.name = ai.mName.C_Str();
      node.parent = parent;
      SetNodeTransform(ToGlm(ai.mTransformation), &node);
    }
    if (node_by_name_.find(ai.mName.C_Str()) == node_by_name_.end())
      node_by_name_[ai.mName.C_Str()] = index;
    for (unsigned c = 0; c < ai.mNumChildren; ++c) {
      const Index child = AddNode(*ai.mChildren[c], index);
      out_->nodes[static_cast<std::size_t>(index)].children.push_back(child);
    }
    return index;
  }

  Status ConvertTextures() {
    embedded_texture_.assign(scene_.mNumTextures, kInvalidIndex);
    for (unsigned i = 0; i < scene_.mNumTextures; ++i) {
      const aiTexture* tex = scene_.mTextures[i];
      if (tex == nullptr || tex->mHeight != 0 || tex->pcData == nullptr) continue;
      AssetImage image;
      image.name = tex->mFilename.C_Str();
      image.mime_type = MimeFromHint(tex->achFormatHint);
      image.bytes.assign(reinterpret_cast<const char*>(tex->pcData), tex->mWidth);
      embedded_texture_[i] = AddTexture(std::move(image));
    }
    return Status::Ok();
  }

  Index AddTexture(AssetImage image) {
    AssetTexture texture;
    texture.name = image.name;
    texture.image = static_cast<Index>(out_->images.size());
    out_->images.push_back(std::move(image));
    out_->textures.push_back(texture);
    return static_cast<Index>(out_->textures.size() - 1);
  }

  // The texture for a material's texture path: embedded ("*N" or a matching file name), else
  // a file next to the model (read once per path).
  Index TextureFor(const aiString& ai_path) {
    const std::string path = ai_path.C_Str();
    if (path.empty()) return kInvalidIndex;
    const std::pair<const aiTexture*, int> embedded =
        scene_.GetEmbeddedTextureAndIndex(path.c_str());
    if (embedded.first != nullptr && embedded.second >= 0 &&
        static_cast<unsigned>(embedded.second) < embedded_texture_.size())
      return embedded_texture_[static_cast<std::size_t>(embedded.second)];
    if (path[0] == '*') return kInvalidIndex;
    const auto cached = file_texture_.find(path);
    if (cached != file_texture_.end()) return cached->second;
    Index result = kInvalidIndex;
    std::filesystem::path file(path);
    if (file.is_relative()) file = std::filesystem::path(path_).parent_path() / file;
    std::ifstream in(file, std::ios::binary);
    if (in) {
      AssetImage image;
      image.name = path;
      image.mime_type = MimeFromHint(file.extension().string());
      image.bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
      if (in.bad() || image.bytes.empty()) {
        result = kInvalidIndex;
      } else {
        result = AddTexture(std::move(image));
      }
    }
    file_texture_[path] = result;
    return result;
  }

  void ConvertMaterials() {
    for (unsigned i = 0; i < scene_.mNumMaterials; ++i) {
      const aiMaterial& m = *scene_.mMaterials[i];
      AssetMaterial material;
      aiString name;
      if (m.Get(AI_MATKEY_NAME, name) == aiReturn_SUCCESS) material.name = name.C_Str();
      aiColor4D color(1.0f, 1.0f, 1.0f, 1.0f);
      if (m.Get(AI_MATKEY_BASE_COLOR, color) != aiReturn_SUCCESS) {
        color = aiColor4D(1.0f, 1.0f, 1.0f, 1.0f);
        aiColor3D diffuse;
        if (m.Get(AI_MATKEY_COLOR_DIFFUSE, diffuse) == aiReturn_SUCCESS)
          color = aiColor4D(diffuse.r, diffuse.g, diffuse.b, 1.0f);
        float opacity = 1.0f;
        if (m.Get(AI_MATKEY_OPACITY, opacity) == aiReturn_SUCCESS && opacity >= 0.0f &&
            opacity <= 1.0f)
          color.a = opacity;
      }
      float metallic = 0.0f;
      if (m.Get(AI_MATKEY_METALLIC_FACTOR, metallic) != aiReturn_SUCCESS) metallic = 0.0f;
      float roughness = 1.0f;
      if (m.Get(AI_MATKEY_ROUGHNESS_FACTOR, roughness) != aiReturn_SUCCESS) roughness = 1.0f;
      Index texture = kInvalidIndex;
      aiString tex_path;
      if (m.GetTexture(aiTextureType_BASE_COLOR, 0, &tex_path) == aiReturn_SUCCESS)
        texture = TextureFor(tex_path);
      if (texture == kInvalidIndex &&
          m.GetTexture(aiTextureType_DIFFUSE, 0, &tex_path) == aiReturn_SUCCESS)
        texture = TextureFor(tex_path);
      int two_sided = 0;
      if (m.Get(AI_MATKEY_TWOSIDED, two_sided) != aiReturn_SUCCESS) two_sided = 0;

      std::string json = "{\"name\":" + JsonString(material.name) +
                         ",\"pbrMetallicRoughness\":{\"baseColorFactor\":[" + JsonNumber(color.r) +
                         "," + JsonNumber(color.g) + "," + JsonNumber(color.b) + "," +
                         JsonNumber(color.a) + "]";
      if (texture != kInvalidIndex)
        json += ",\"baseColorTexture\":{\"index\":" + std::to_string(texture) + "}";
      json += ",\"metallicFactor\":" + JsonNumber(std::clamp(metallic, 0.0f, 1.0f)) +
              ",\"roughnessFactor\":" + JsonNumber(std::clamp(roughness, 0.0f, 1.0f)) + "}";
      if (color.a < 1.0f) json += ",\"alphaMode\":\"BLEND\"";
      if (two_sided != 0) json += ",\"doubleSided\":true";
      json += "}";
      material.json = json;
      out_->materials.push_back(std::move(material));
    }
  }

  // Copies vertex `v` of `mesh` (with its influences) to the end of `prim`.
  void CopyVertex(const aiMesh& mesh, unsigned v,
                  const std::vector<std::vector<std::pair<float, Index>>>& influences, int sets,
                  AssetPrimitive* prim) const {
    prim->positions.emplace_back(mesh.mVertices[v].x, mesh.mVertices[v].y, mesh.mVertices[v].z);
    if (mesh.mNormals != nullptr) {
      prim->normals.push_back(UnitOr(mesh.mNormals[v], glm::vec3(0.0f, 0.0f, 1.0f)));
      if (mesh.mTangents != nullptr) {
        const glm::vec3 n = prim->normals.back();
        const glm::vec3 t = UnitOr(mesh.mTangents[v], glm::vec3(1.0f, 0.0f, 0.0f));
        float w = 1.0f;
        if (mesh.mBitangents != nullptr) {
          const aiVector3D& b = mesh.mBitangents[v];
          if (glm::dot(glm::cross(n, t), glm::vec3(b.x, b.y, b.z)) < 0.0f) w = -1.0f;
        }
        prim->tangents.emplace_back(t, w);
      }
    }
    std::size_t set = 0;
    for (unsigned c = 0; c < AI_MAX_NUMBER_OF_TEXTURECOORDS; ++c) {
      if (mesh.mTextureCoords[c] == nullptr) continue;
      prim->texcoords[set++].emplace_back(mesh.mTextureCoords[c][v].x, mesh.mTextureCoords[c][v].y);
    }
    set = 0;
    for (unsigned c = 0; c < AI_MAX_NUMBER_OF_COLOR_SETS; ++c) {
      if (mesh.mColors[c] == nullptr) continue;
      const aiColor4D& col = mesh.mColors[c][v];
      prim->colors[set++].emplace_back(col.r, col.g, col.b, col.a);
    }
    if (sets > 0) {
      const auto& list = influences[v];
      float sum = 0.0f;
      for (const auto& p : list) sum += p.first;
      for (int s = 0; s < sets; ++s) {
        glm::u16vec4 joints(0);
        glm::vec4 weights(0.0f);
        for (int k = 0; k < 4; ++k) {
          const std::size_t at = static_cast<std::size_t>(s * 4 + k);
          if (at >= list.size()) break;
          joints[k] = static_cast<std::uint16_t>(list[at].second);
          weights[k] = sum > 0.0f ? list[at].first / sum : 0.0f;
        }
        prim->joints[static_cast<std::size_t>(s)].push_back(joints);
        prim->weights[static_cast<std::size_t>(s)].push_back(weights);
      }
    }
  }

  Status ConvertMesh(unsigned mesh_index) {
    const aiMesh& mesh = *scene_.mMeshes[mesh_index];
    const std::string where =
        "mesh " + std::to_string(mesh_index) + " (" + mesh.mName.C_Str() + ")";
    AssetMesh asset_mesh;
    asset_mesh.name = mesh.mName.C_Str();

    // Influences per vertex, as (weight, joint).
    std::vector<std::vector<std::pair<float, Index>>> influences;
    int sets = 0;
    if (mesh.mNumBones > 0) {
      if (mesh.mNumBones > 65535) return Error(where, "more than 65535 bones");
      AssetSkin skin;
      skin.name = mesh.mName.C_Str();
      influences.resize(mesh.mNumVertices);
      for (unsigned b = 0; b < mesh.mNumBones; ++b) {
        const aiBone& bone = *mesh.mBones[b];
        const auto node = node_by_name_.find(bone.mName.C_Str());
        if (node == node_by_name_.end())
          return Error(where, std::string("bone '") + bone.mName.C_Str() + "' names no node");
        skin.joints.push_back(node->second);
        glm::mat4 ibm(ToGlm(bone.mOffsetMatrix));
        ibm[0][3] = 0.0f;
        ibm[1][3] = 0.0f;
        ibm[2][3] = 0.0f;
        ibm[3][3] = 1.0f;
        skin.inverse_bind_matrices.push_back(ibm);
        for (unsigned w = 0; w < bone.mNumWeights; ++w) {
          const aiVertexWeight& vw = bone.mWeights[w];
          if (vw.mVertexId >= mesh.mNumVertices)
            return Error(where, std::string("bone '") + bone.mName.C_Str() + "' weights vertex " +
                                    std::to_string(vw.mVertexId) + " of " +
                                    std::to_string(mesh.mNumVertices));
          if (!(vw.mWeight > 0.0f) || !std::isfinite(vw.mWeight)) continue;
          influences[vw.mVertexId].emplace_back(vw.mWeight, static_cast<Index>(b));
        }
      }
      std::size_t most = 1;
      for (auto& list : influences) {
        std::sort(list.begin(), list.end(), [](const auto& a, const auto& b) {
          return a.first != b.first ? a.first > b.first : a.second < b.second;
        });
        most = std::max(most, list.size());
      }
      sets = static_cast<int>((most + 3) / 4);
      mesh_skin_[mesh_index] = static_cast<Index>(out_->skins.size());
      out_->skins.push_back(std::move(skin));
    }

    // Faces by kind: 0 triangles, 1 lines, 2 points.
    std::vector<std::uint32_t> by_kind[3];
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      int kind = -1;
      if (face.mNumIndices == 3) kind = 0;
      if (face.mNumIndices == 2) kind = 1;
      if (face.mNumIndices == 1) kind = 2;
      if (kind < 0)
        return Error(where, "face " + std::to_string(f) + " has " +
                                std::to_string(face.mNumIndices) + " corners after triangulation");
      for (unsigned k = 0; k < face.mNumIndices; ++k) {
        if (face.mIndices[k] >= mesh.mNumVertices)
          return Error(where, "face " + std::to_string(f) + " indexes vertex " +
                                  std::to_string(face.mIndices[k]) + " of " +
                                  std::to_string(mesh.mNumVertices));
        by_kind[kind].push_back(face.mIndices[k]);
      }
    }
    const int kinds =
        int(!by_kind[0].empty()) + int(!by_kind[1].empty()) + int(!by_kind[2].empty());
    static const PrimitiveMode kModes[3] = {PrimitiveMode::kTriangles, PrimitiveMode::kLines,
                                            PrimitiveMode::kPoints};
    std::size_t uv_sets = 0, color_sets = 0;
    for (unsigned c = 0; c < AI_MAX_NUMBER_OF_TEXTURECOORDS; ++c)
      uv_sets += mesh.mTextureCoords[c] != nullptr ? 1 : 0;
    for (unsigned c = 0; c < AI_MAX_NUMBER_OF_COLOR_SETS; ++c)
      color_sets += mesh.mColors[c] != nullptr ? 1 : 0;
    auto make_primitive = [&](PrimitiveMode mode) {
      AssetPrimitive prim;
      prim.mode = mode;
      prim.material = mesh.mMaterialIndex < scene_.mNumMaterials
                          ? static_cast<Index>(mesh.mMaterialIndex)
                          : kInvalidIndex;
      prim.texcoords.resize(uv_sets);
      prim.colors.resize(color_sets);
      prim.joints.resize(static_cast<std::size_t>(sets));
      prim.weights.resize(static_cast<std::size_t>(sets));
      return prim;
    };
    if (kinds == 0) {
      AssetPrimitive prim = make_primitive(PrimitiveMode::kPoints);
      for (unsigned v = 0; v < mesh.mNumVertices; ++v) CopyVertex(mesh, v, influences, sets, &prim);
      asset_mesh.primitives.push_back(std::move(prim));
    }
    for (int kind = 0; kind < 3; ++kind) {
      if (by_kind[kind].empty()) continue;
      AssetPrimitive prim = make_primitive(kModes[kind]);
      if (kinds == 1) {
        for (unsigned v = 0; v < mesh.mNumVertices; ++v)
          CopyVertex(mesh, v, influences, sets, &prim);
        prim.indices = std::move(by_kind[kind]);
      } else {
        std::vector<std::int64_t> remap(mesh.mNumVertices, -1);
        for (const std::uint32_t v : by_kind[kind]) remap[v] = 0;
        std::uint32_t next = 0;
        for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
          if (remap[v] < 0) continue;
          remap[v] = next++;
          CopyVertex(mesh, v, influences, sets, &prim);
        }
        prim.indices.reserve(by_kind[kind].size());
        for (const std::uint32_t v : by_kind[kind])
          prim.indices.push_back(static_cast<std::uint32_t>(remap[v]));
      }
      asset_mesh.primitives.push_back(std::move(prim));
    }
    out_->meshes.push_back(std::move(asset_mesh));
    return Status::Ok();
  }

  void AttachMeshes() {
    const std::size_t count = ai_nodes_.size();
    for (std::size_t n = 0; n < count; ++n) {
      const aiNode& ai = *ai_nodes_[n];
      if (ai.mNumMeshes == 1) {
        out_->nodes[n].mesh = static_cast<Index>(ai.mMeshes[0]);
        out_->nodes[n].skin = mesh_skin_[ai.mMeshes[0]];
        continue;
      }
      for (unsigned k = 0; k < ai.mNumMeshes; ++k) {
        AssetNode child;
        child.name = std::string(ai.mName.C_Str()) + "#" + std::to_string(k);
        child.parent = static_cast<Index>(n);
        child.mesh = static_cast<Index>(ai.mMeshes[k]);
        child.skin = mesh_skin_[ai.mMeshes[k]];
        out_->nodes[n].children.push_back(static_cast<Index>(out_->nodes.size()));
        out_->nodes.push_back(std::move(child));
      }
    }
  }

  template <typename Key, typename ToValues>
  void AddSampler(const Key* keys, unsigned count, double ticks_per_second, int components,
                  Index node, AnimationPath path, ToValues to_values, AssetAnimation* anim) {
    if (keys == nullptr || count == 0) return;
    AssetAnimationSampler sampler;
    sampler.components = components;
    sampler.interpolation = Interpolation::kLinear;
    for (unsigned k = 0; k < count; ++k) {
      const auto t = static_cast<float>(keys[k].mTime / ticks_per_second);
      if (!std::isfinite(t)) continue;
      if (!sampler.times.empty() && !(t > sampler.times.back())) continue;
      sampler.times.push_back(t);
      to_values(keys[k].mValue, &sampler.values);
    }
    AssetAnimationChannel channel;
    channel.sampler = static_cast<Index>(anim->samplers.size());
    channel.node = node;
    channel.path = path;
    anim->samplers.push_back(std::move(sampler));
    anim->channels.push_back(channel);
  }

  Status ConvertAnimation(unsigned index) {
    const aiAnimation& ai = *scene_.mAnimations[index];
    AssetAnimation anim;
    anim.name = ai.mName.C_Str();
    const double tps = ai.mTicksPerSecond > 0.0 ? ai.mTicksPerSecond : 25.0;
    for (unsigned c = 0; c < ai.mNumChannels; ++c) {
      const aiNodeAnim& ch = *ai.mChannels[c];
      const auto node = node_by_name_.find(ch.mNodeName.C_Str());
      if (node == node_by_name_.end())
        return Error("animation " + std::to_string(index) + " (" + anim.name + ")",
                     std::string("channel for unknown node '") + ch.mNodeName.C_Str() + "'");
      AddSampler(
          ch.mPositionKeys, ch.mNumPositionKeys, tps, 3, node->second, AnimationPath::kTranslation,
          [](const aiVector3D& v, std::vector<float>* out) {
            out->insert(out->end(), {v.x, v.y, v.z});
          },
          &anim);
      AddSampler(
          ch.mRotationKeys, ch.mNumRotationKeys, tps, 4, node->second, AnimationPath::kRotation,
          [](const aiQuaternion& q, std::vector<float>* out) {
            // aiQuaternion is (w, x, y, z); glTF stores x y z w.
            out->insert(out->end(), {q.x, q.y, q.z, q.w});
          },
          &anim);
      AddSampler(
          ch.mScalingKeys, ch.mNumScalingKeys, tps, 3, node->second, AnimationPath::kScale,
          [](const aiVector3D& v, std::vector<float>* out) {
            out->insert(out->end(), {v.x, v.y, v.z});
          },
          &anim);
    }
    out_->animations.push_back(std::move(anim));
    return Status::Ok();
  }

  const aiScene& scene_;
  const std::string& path_;
  Asset* out_;
  std::vector<const aiNode*> ai_nodes_;
  std::map<std::string, Index> node_by_name_;
  std::vector<Index> embedded_texture_;
  std::map<std::string, Index> file_texture_;
  std::vector<Index> mesh_skin_;
};

// XML nesting depth of `text` (elements only; comments, CDATA, declarations and processing
// instructions skipped), stopping once it passes `limit`.
int XmlDepth(std::string_view text, int limit) {
  int depth = 0, deepest = 0;
  for (std::size_t i = 0; i < text.size() && deepest <= limit; ++i) {
    if (text[i] != '<' || i + 1 >= text.size()) continue;
    const char c = text[i + 1];
    if (c == '!' || c == '?') {
      const char* end = text.compare(i, 4, "<!--") == 0        ? "-->"
                        : text.compare(i, 9, "<![CDATA[") == 0 ? "]]>"
                                                               : ">";
      const std::size_t e = text.find(end, i + 2);
      if (e == std::string_view::npos) break;
      i = e;
      continue;
    }
    if (c == '/') {
      --depth;
      continue;
    }
    const std::size_t close = text.find('>', i + 1);
    if (close == std::string_view::npos) break;
    if (text[close - 1] != '/') deepest = std::max(deepest, ++depth);
    i = close;
  }
  return deepest;
}

// The first COLLADA index list (<p>, <v>, <vcount>, <h>, <int_array>) whose text holds a
// character that is not part of an integer (digits, signs, white space), or an empty view.
// Assimp 5.2's COLLADA reader parses these lists with an integer reader that does not stop at
// such a character: one stray byte in a 4 KB file made it allocate without bound (16 GB and a
// bad_alloc after 77 s; found by fuzz_assimp, docs/reliability.md). Linear in the file.
std::string_view BadColladaIndexList(std::string_view text) {
  static const std::string_view kLists[] = {"p", "v", "vcount", "h", "int_array"};
  for (std::size_t i = text.find('<'); i != std::string_view::npos; i = text.find('<', i + 1)) {
    std::size_t e = i + 1;
    while (e < text.size() && text[e] != '>' && text[e] != '/' && text[e] != ' ' &&
           text[e] != '\t' && text[e] != '\n' && text[e] != '\r') {
      ++e;
    }
    const std::string_view name = text.substr(i + 1, e - i - 1);
    bool list = false;
    for (const std::string_view l : kLists) list = list || name == l;
    if (!list) continue;
    const std::size_t open_end = text.find('>', e);
    if (open_end == std::string_view::npos || text[open_end - 1] == '/') continue;
    const std::size_t close = text.find('<', open_end);
    const std::string_view body = text.substr(
        open_end + 1, (close == std::string_view::npos ? text.size() : close) - open_end - 1);
    for (const char c : body) {
      const bool ok = (c >= '0' && c <= '9') || c == '-' || c == '+' || c == ' ' || c == '\t' ||
                      c == '\n' || c == '\r';
      if (!ok) return name;
    }
    if (close == std::string_view::npos) break;
    i = close - 1;
  }
  return {};
}

// The value of attribute `name` in the start tag `tag` (the text between '<' and '>'), or
// an empty view.
std::string_view XmlAttribute(std::string_view tag, std::string_view name) {
  for (std::size_t i = tag.find(name); i != std::string_view::npos; i = tag.find(name, i + 1)) {
    const bool starts = i > 0 && (tag[i - 1] == ' ' || tag[i - 1] == '\t' || tag[i - 1] == '\n' ||
                                  tag[i - 1] == '\r');
    std::size_t e = i + name.size();
    while (e < tag.size() && tag[e] == ' ') ++e;
    if (!starts || e >= tag.size() || tag[e] != '=') continue;
    ++e;
    while (e < tag.size() && tag[e] == ' ') ++e;
    if (e >= tag.size() || (tag[e] != '"' && tag[e] != '\'')) continue;
    const std::size_t close = tag.find(tag[e], e + 1);
    if (close == std::string_view::npos) return {};
    return tag.substr(e + 1, close - e - 1);
  }
  return {};
}

// A non-negative decimal attribute value, or `fallback` when absent; -1 when not a number.
std::int64_t XmlCount(std::string_view value, std::int64_t fallback) {
  if (value.empty()) return fallback;
  std::int64_t n = 0;
  for (const char c : value) {
    if (c < '0' || c > '9' || n > (std::int64_t{1} << 40)) return -1;
    n = n * 10 + (c - '0');
  }
  return n;
}

// The first COLLADA <accessor> that reads past the array it names (offset + count x stride
// values of an array of `count` values, COLLADA 1.4.1 section 5), as a message, or an empty
// string. Assimp 5.2 reads such accessors without a bound check (a read past the heap block,
// found by fuzz_assimp: stride="32" over a 360-value array). Linear in the file.
std::string BadColladaAccessor(std::string_view text) {
  std::map<std::string_view, std::int64_t> arrays;  // id -> value count
  std::vector<std::string_view> accessors;
  for (std::size_t i = text.find('<'); i != std::string_view::npos; i = text.find('<', i + 1)) {
    const std::size_t close = text.find('>', i);
    if (close == std::string_view::npos) break;
    const std::string_view tag = text.substr(i + 1, close - i - 1);
    std::size_t e = 0;
    while (e < tag.size() && tag[e] != ' ' && tag[e] != '\t' && tag[e] != '\n' && tag[e] != '\r' &&
           tag[e] != '/') {
      ++e;
    }
    const std::string_view name = tag.substr(0, e);
    if (name == "accessor") {
      accessors.push_back(tag);
    } else if (name.size() > 6 && name.substr(name.size() - 6) == "_array") {
      const std::string_view id = XmlAttribute(tag, "id");
      if (!id.empty()) arrays[id] = XmlCount(XmlAttribute(tag, "count"), 0);
    }
    i = close;
  }
  for (const std::string_view tag : accessors) {
    std::string_view source = XmlAttribute(tag, "source");
    if (!source.empty() && source[0] == '#') source.remove_prefix(1);
    const auto it = arrays.find(source);
    if (it == arrays.end()) continue;  // Assimp refuses an accessor of an unknown source
    const std::int64_t count = XmlCount(XmlAttribute(tag, "count"), 0);
    const std::int64_t stride = XmlCount(XmlAttribute(tag, "stride"), 1);
    const std::int64_t offset = XmlCount(XmlAttribute(tag, "offset"), 0);
    if (count < 0 || stride < 0 || offset < 0 || it->second < 0 ||
        offset + count * stride > it->second) {
      return "COLLADA <accessor source=\"#" + std::string(source) + "\" count=\"" +
             std::string(XmlAttribute(tag, "count")) + "\" stride=\"" +
             std::string(XmlAttribute(tag, "stride")) + "\"> reads past the " +
             std::to_string(it->second) + " values of its array";
    }
  }
  return std::string();
}

// Why the counts in an OFF header cannot be right for a file of `text.size()` bytes, or an
// empty string. Assimp 5.2's OFF reader reserves the declared faces before reading them (an
// 828-byte file declaring 10^35 faces took 22 GB and 63 s before bad_alloc; found by
// fuzz_assimp). Each vertex needs at least 6 bytes ("0 0 0\n") and each face at least 8
// ("3 0 1 2\n"), so larger counts are refused before Assimp.
std::string BadOffHeader(std::string_view text) {
  std::size_t i = 0;
  const auto skip = [&] {
    for (;;) {
      while (i < text.size() &&
             (text[i] == ' ' || text[i] == '\t' || text[i] == '\r' || text[i] == '\n')) {
        ++i;
      }
      if (i < text.size() && text[i] == '#') {
        while (i < text.size() && text[i] != '\n') ++i;
        continue;
      }
      return;
    }
  };
  skip();
  // The keyword (OFF, COFF, NOFF, STOFF, ...), which Assimp also reads when it is missing.
  if (i < text.size() && (text[i] < '0' || text[i] > '9')) {
    while (i < text.size() && text[i] != ' ' && text[i] != '\t' && text[i] != '\r' &&
           text[i] != '\n') {
      ++i;
    }
  }
  const double bytes = static_cast<double>(text.size());
  const char* const what[] = {"vertices", "faces"};
  const double per[] = {6.0, 8.0};
  for (int k = 0; k < 2; ++k) {
    skip();
    double n = 0.0;
    const std::size_t start = i;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9') n = n * 10.0 + (text[i++] - '0');
    if (i == start) return std::string();  // not a count: Assimp reports the header itself
    if (n * per[k] > bytes) {
      char message[160];
      std::snprintf(message, sizeof(message),
                    "the OFF header declares %.0f %s, more than a file of %.0f bytes holds", n,
                    what[k], bytes);
      return message;
    }
  }
  return std::string();
}

// What Assimp is not given: files of an extension it does not list (it would try every
// importer on their content, and Assimp 5.2 leaks memory in several of them on bad input),
// 3MF (Assimp 5.2's 3MF importer leaks on failed imports), and XML nested deeper than
// limits::kMaxXmlDepth (its Collada reader recurses per node and overflows the stack), and
// COLLADA index lists with a character that is not part of an integer (BadColladaIndexList)
// and accessors reading past their arrays (BadColladaAccessor), and OFF headers declaring more
// vertices or faces than the file can hold (BadOffHeader).
Status CheckBeforeAssimp(const std::string& path, const std::string& ext,
                         const Assimp::Importer& importer) {
  if (ext.empty() || !importer.IsExtensionSupported(ext)) {
    return Status::Unsupported(
        path + ": no importer reads '" + (ext.empty() ? std::string("(no extension)") : ext) +
        "' files (glTF, OBJ, PLY and the formats Assimp lists by extension)");
  }
  if (ext == ".3mf") {
    return Status::Unsupported(path +
                               ": 3MF is not read (Assimp 5.2's 3MF importer leaks memory on bad "
                               "files; docs/reliability.md)");
  }
  std::string bytes;
  Status s = ReadFileBytes(path, "a model file", &bytes);
  if (!s.ok()) return s;
  // XML by extension (the formats Assimp reads as XML) or by its declaration near the start.
  static const char* const kXml[] = {".dae", ".xml", ".x3d", ".x3db", ".irr",     ".irrmesh",
                                     ".xgl", ".zgl", ".amf", ".ogex", ".mesh.xml"};
  const std::string head = AsciiLower(std::string_view(bytes).substr(0, 1024));
  bool xml = head.find("<?xml") != std::string::npos || head.find("<collada") != std::string::npos;
  for (const char* e : kXml) xml = xml || ext == e;
  if (xml && XmlDepth(bytes, limits::kMaxXmlDepth) > limits::kMaxXmlDepth) {
    return Status::InvalidInput(path + ": XML elements nested deeper than " +
                                std::to_string(limits::kMaxXmlDepth) + " levels: refused");
  }
  if (ext == ".dae" || head.find("<collada") != std::string::npos) {
    const std::string_view list = BadColladaIndexList(bytes);
    if (!list.empty()) {
      return Status::InvalidInput(path + ": COLLADA <" + std::string(list) +
                                  "> holds a character that is not part of an integer: refused");
    }
    const std::string accessor = BadColladaAccessor(bytes);
    if (!accessor.empty()) return Status::InvalidInput(path + ": " + accessor + ": refused");
  }
  if (ext == ".off") {
    const std::string off = BadOffHeader(bytes);
    if (!off.empty()) return Status::InvalidInput(path + ": " + off + ": refused");
  }
  return Status::Ok();
}

}  // namespace

Status ImportAssimp(const std::string& path, Asset* out) {
  *out = Asset();
  const std::string ext = LowerExtension(path);
  if (ext == ".gltf" || ext == ".glb")
    return Status::Unsupported(path +
                               ": glTF is read by ImportGltf (tinygltf), never by Assimp, which "
                               "misreads normalised weights and quantised positions");
  try {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
      std::string bytes;  // the reader's message: missing, a directory, a device
      const Status r = ReadFileBytes(path, "a model file", &bytes);
      return r.ok() ? Status::IoError(path + ": cannot open") : r;
    }
    Assimp::Importer importer;
    Status guard = CheckBeforeAssimp(path, ext, importer);
    if (!guard.ok()) return guard;
    const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                           aiProcess_FlipUVs | aiProcess_ValidateDataStructure;
    const aiScene* scene = importer.ReadFile(path, flags);
    if (scene == nullptr)
      return Status::InvalidInput(path + ": Assimp: " + importer.GetErrorString());
    if (scene->mRootNode == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0)
      return Status::InvalidInput(path + ": Assimp: incomplete scene");
    // Node count and depth, walked without recursion, before the converter recurses.
    std::vector<std::pair<const aiNode*, int>> stack{{scene->mRootNode, 1}};
    std::uint64_t nodes = 0;
    while (!stack.empty()) {
      const auto [node, depth] = stack.back();
      stack.pop_back();
      if (++nodes > limits::kMaxNodes || depth > limits::kMaxNodeDepth) {
        return Status::InvalidInput(path + ": the scene has more than " +
                                    std::to_string(limits::kMaxNodes) +
                                    " nodes or a node nested deeper than " +
                                    std::to_string(limits::kMaxNodeDepth) + " levels: refused");
      }
      for (unsigned c = 0; c < node->mNumChildren; ++c) {
        if (node->mChildren[c] != nullptr) stack.emplace_back(node->mChildren[c], depth + 1);
      }
    }
    Converter converter(*scene, path, out);
    Status s = converter.Run();
    if (!s.ok()) {
      *out = Asset();
      return s;
    }
    s = ValidateAsset(*out);
    if (!s.ok()) *out = Asset();
    return s;
  } catch (const std::exception& e) {
    *out = Asset();
    return Status::Internal(path + ": Assimp: " + e.what());
  } catch (...) {
    *out = Asset();
    return Status::Internal(path + ": Assimp: unknown exception");
  }
}

}  // namespace dermis

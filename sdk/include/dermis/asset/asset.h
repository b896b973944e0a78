// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The neutral asset module: meshes, materials, textures, node hierarchy, skins and
/// animation clips as every importer produces them and every exporter consumes them.
///
/// Offline code (std + GLM only). Plugins (glTF via tinygltf, other formats via Assimp) see
/// only this module; runtime code never sees plugins. The layout follows glTF 2.0 closely so a
/// glTF round trip is lossless, but every attribute is decoded: positions are float triples
/// whatever the source encoding (strided, normalised integers, sparse, KHR_mesh_quantization).
///
/// Conventions: units are the source's (metres for glTF), right-handed, Y up for glTF sources.
/// Indices are 0-based; -1 (kInvalidIndex) means "none".
#pragma once

#include <cstdint>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <string>
#include <vector>

#include "dermis/core/types.h"

namespace dermis {

/// glTF primitive topology (the glTF `mode` codes).
enum class PrimitiveMode : std::uint8_t {
  kPoints = 0,
  kLines = 1,
  kLineLoop = 2,
  kLineStrip = 3,
  kTriangles = 4,
  kTriangleStrip = 5,
  kTriangleFan = 6,
};

/// One morph target: per-vertex deltas (each empty or of the primitive's vertex count).
struct AssetMorphTarget {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec3> tangents;
};

/// A drawable piece of a mesh with one material. All attribute arrays that are present have
/// exactly positions.size() entries.
struct AssetPrimitive {
  PrimitiveMode mode = PrimitiveMode::kTriangles;
  std::vector<glm::vec3> positions;  ///< Mesh space (the bind shape of a skinned mesh).
  std::vector<glm::vec3> normals;    ///< Unit length, or empty.
  std::vector<glm::vec4> tangents;   ///< xyz unit, w = +-1 handedness, or empty.
  std::vector<std::vector<glm::vec2>> texcoords;  ///< TEXCOORD_0, TEXCOORD_1, ...
  std::vector<std::vector<glm::vec4>> colors;     ///< COLOR_0, ... (RGB sources get a = 1).
  /// JOINTS_n / WEIGHTS_n sets, joints index the skin's joint list (not nodes). Weights of
  /// each vertex over all sets sum to 1 (importers renormalise; all-zero rows stay zero).
  std::vector<std::vector<glm::u16vec4>> joints;
  std::vector<std::vector<glm::vec4>> weights;
  std::vector<std::uint32_t> indices;  ///< Empty: not indexed (vertex order is the order).
  std::vector<AssetMorphTarget> targets;
  Index material = kInvalidIndex;  ///< Into Asset::materials.
};

/// A mesh: primitives plus default morph weights. Instanced by any number of nodes.
struct AssetMesh {
  std::string name;
  std::vector<AssetPrimitive> primitives;
  std::vector<float> weights;  ///< Default morph target weights (may be empty).
};

/// A material kept opaque: `json` is the glTF 2.0 material object as compact JSON text whose
/// texture indices refer to Asset::textures. Importers of other formats write an equivalent
/// glTF material (at least the name and a base colour).
struct AssetMaterial {
  std::string name;
  std::string json = "{}";
};

/// A texture: an image plus a sampler.
struct AssetTexture {
  std::string name;
  Index image = kInvalidIndex;    ///< Into Asset::images.
  Index sampler = kInvalidIndex;  ///< Into Asset::samplers, or none (repeat, auto filter).
};

/// An image kept as the encoded bytes of its file (PNG, JPEG, ...), never decoded.
struct AssetImage {
  std::string name;
  std::string mime_type;  ///< "image/png", "image/jpeg", ... (may be empty if unknown).
  std::string bytes;      ///< Encoded file bytes.
};

/// A texture sampler (glTF codes; -1 = unset).
struct AssetSampler {
  std::string name;
  int mag_filter = -1;
  int min_filter = -1;
  int wrap_s = 10497;
  int wrap_t = 10497;
};

/// A node of the hierarchy. Its local transform is either TRS or a matrix.
struct AssetNode {
  std::string name;
  Index parent = kInvalidIndex;  ///< Derived from children lists by the importer.
  std::vector<Index> children;
  glm::dvec3 translation{0.0};
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};  ///< glm order (w, x, y, z); unit length.
  glm::dvec3 scale{1.0};
  bool has_matrix = false;  ///< True: `matrix` is the local transform, TRS unused.
  glm::dmat4 matrix{1.0};   ///< Column-major like glTF.
  Index mesh = kInvalidIndex;
  Index skin = kInvalidIndex;
  std::vector<double> weights;  ///< Morph weights overriding the mesh's (may be empty).
};

/// A skin: joints and their inverse bind matrices (identity when the source has none).
struct AssetSkin {
  std::string name;
  std::vector<Index> joints;                     ///< Node indices.
  std::vector<glm::mat4> inverse_bind_matrices;  ///< One per joint, last row (0, 0, 0, 1).
  bool has_inverse_bind_matrices = true;         ///< False when the source gave none (identity).
  Index skeleton = kInvalidIndex;                ///< Optional common root node.
};

enum class AnimationPath : std::uint8_t { kTranslation, kRotation, kScale, kWeights };
enum class Interpolation : std::uint8_t { kLinear, kStep, kCubicSpline };

/// Keyframes of one animated property. `values` holds, per keyframe, `components` floats
/// (3 for T/S, 4 for R as x y z w like glTF, the morph target count for weights); for
/// CUBICSPLINE each keyframe holds in-tangent, value, out-tangent (3 * components floats).
struct AssetAnimationSampler {
  std::vector<float> times;  ///< Seconds, strictly increasing.
  std::vector<float> values;
  int components = 0;
  Interpolation interpolation = Interpolation::kLinear;
};

struct AssetAnimationChannel {
  Index sampler = kInvalidIndex;  ///< Into AssetAnimation::samplers.
  Index node = kInvalidIndex;
  AnimationPath path = AnimationPath::kTranslation;
};

/// An animation clip.
struct AssetAnimation {
  std::string name;
  std::vector<AssetAnimationSampler> samplers;
  std::vector<AssetAnimationChannel> channels;
  /// The largest keyframe time of any sampler (seconds); 0 for an empty clip.
  double Duration() const;
};

struct AssetScene {
  std::string name;
  std::vector<Index> nodes;  ///< Root nodes.
};

/// A whole asset.
struct Asset {
  std::string source;  ///< The file it came from (for messages).
  std::string generator, copyright;
  std::vector<AssetMesh> meshes;
  std::vector<AssetMaterial> materials;
  std::vector<AssetTexture> textures;
  std::vector<AssetImage> images;
  std::vector<AssetSampler> samplers;
  std::vector<AssetNode> nodes;
  std::vector<AssetSkin> skins;
  std::vector<AssetAnimation> animations;
  std::vector<AssetScene> scenes;
  Index default_scene = kInvalidIndex;
};

}  // namespace dermis

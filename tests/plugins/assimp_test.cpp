// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// ImportAssimp: scans (OBJ, PLY), a skinned and animated COLLADA file written by Assimp's own
// exporter from a scene built here, and Assimp reading the .glb files that ExportGltf writes.
#include "dermis/plugins/assimp.h"

#include <assimp/scene.h>
#include <unistd.h>

#include <assimp/Exporter.hpp>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <glm/gtc/quaternion.hpp>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "dermis/asset/asset.h"
#include "dermis/plugins/gltf.h"
#include "support/assimp_counts.h"

namespace dermis {
namespace {

namespace fs = std::filesystem;

const char* kData = "../shared/data";

bool HaveData() { return fs::exists(fs::path(kData) / "README.md"); }

std::string TempPath(const std::string& name) {
  return (fs::temp_directory_path() /
          ("dermis_assimp_test_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

Index NodeByName(const Asset& asset, const std::string& name) {
  for (std::size_t i = 0; i < asset.nodes.size(); ++i)
    if (asset.nodes[i].name == name) return static_cast<Index>(i);
  return kInvalidIndex;
}

struct MeshCounts {
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  std::size_t distinct_positions = 0;
  glm::vec3 lo{1e30f}, hi{-1e30f};
};

MeshCounts CountTriangleMeshes(const Asset& asset) {
  MeshCounts c;
  std::set<std::tuple<float, float, float>> distinct;
  for (const AssetMesh& mesh : asset.meshes) {
    for (const AssetPrimitive& prim : mesh.primitives) {
      REQUIRE(prim.mode == PrimitiveMode::kTriangles);
      c.vertices += prim.positions.size();
      c.triangles += (prim.indices.empty() ? prim.positions.size() : prim.indices.size()) / 3;
      for (const glm::vec3& p : prim.positions) {
        distinct.insert({p.x, p.y, p.z});
        c.lo = glm::min(c.lo, p);
        c.hi = glm::max(c.hi, p);
      }
    }
  }
  c.distinct_positions = distinct.size();
  return c;
}

void WriteText(const std::string& path, const char* text) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  REQUIRE(f != nullptr);
  std::fputs(text, f);
  std::fclose(f);
}

TEST_CASE("ImportAssimp refuses glTF and reports missing files", "[assimp]") {
  Asset asset;
  Status s = ImportAssimp("whatever/model.GLB", &asset);
  CHECK(s.code() == StatusCode::kUnsupported);
  CHECK(s.message().find("model.GLB") != std::string::npos);
  CHECK(s.message().find("ImportGltf") != std::string::npos);
  s = ImportAssimp("model.gltf", &asset);
  CHECK(s.code() == StatusCode::kUnsupported);
  s = ImportAssimp("/nonexistent/dir/model.fbx", &asset);
  CHECK(s.code() == StatusCode::kIoError);
  CHECK(s.message().find("/nonexistent/dir/model.fbx") != std::string::npos);

  // A file Assimp cannot parse: the message names it and carries Assimp's error.
  const std::string bad = TempPath("bad.obj");
  WriteText(bad, "v 0 0 0\nv 1 0 0\nf 1 2 7\n");
  s = ImportAssimp(bad, &asset);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find(bad) != std::string::npos);
  fs::remove(bad);
}

TEST_CASE("ImportAssimp reads the bunny scans", "[assimp]") {
  if (!HaveData()) {
    WARN("skipped: ../shared/data is absent");
    return;
  }
  SECTION("npm bunny OBJ: 1,839 vertices, 3,674 triangles") {
    Asset asset;
    const Status s = ImportAssimp(std::string(kData) + "/scans/bunny-npm-1839v.obj", &asset);
    REQUIRE(s.ok());
    REQUIRE(asset.meshes.size() == 1);
    const MeshCounts c = CountTriangleMeshes(asset);
    CHECK(c.distinct_positions == 1839);
    // JoinIdenticalVertices undoes Assimp's one-vertex-per-corner OBJ output.
    CHECK(c.vertices == 1839);
    CHECK(c.triangles == 3674);
    CHECK(c.lo.x == Approx(-4.958).margin(1e-3));
    CHECK(c.hi.y == Approx(9.655).margin(1e-3));
    CHECK(c.hi.z == Approx(3.811).margin(1e-3));
    // One scene whose only root is Assimp's root node, which draws the mesh (directly or
    // through a child).
    REQUIRE(asset.scenes.size() == 1);
    CHECK(asset.scenes[0].nodes == std::vector<Index>{0});
    int drawing = 0;
    for (const AssetNode& node : asset.nodes) drawing += node.mesh == 0 ? 1 : 0;
    CHECK(drawing == 1);
    // Assimp's OBJ reader makes a default material; it becomes glTF-like JSON.
    REQUIRE(asset.materials.size() >= 1);
    CHECK(asset.materials[0].json.find("\"baseColorFactor\":[") != std::string::npos);
  }
  SECTION("Stanford PLY: 69,451 triangles over the 34,834 vertices faces use") {
    Asset asset;
    const Status s = ImportAssimp(std::string(kData) + "/scans/bun_zipper.ply", &asset);
    REQUIRE(s.ok());
    const MeshCounts c = CountTriangleMeshes(asset);
    CHECK(c.triangles == 69451);
    // Assimp's PLY reader emits one vertex per face corner, so the 1,113 vertices no face uses
    // are gone, and joining leaves the 34,834 used ones (README: 35,947 with 34,834 used).
    CHECK(c.distinct_positions == 34834);
    CHECK(c.vertices == 34834);
    CHECK(c.lo.x == Approx(-0.0947).margin(1e-4));
    CHECK(c.lo.y == Approx(0.0330).margin(1e-4));
    CHECK(c.hi.y == Approx(0.1873).margin(1e-4));
    CHECK(c.hi.z == Approx(0.0588).margin(1e-4));
  }
}

TEST_CASE("ImportAssimp splits faces by kind and flips v to glTF's convention", "[assimp]") {
  // A quad with UVs, a line and a point in one OBJ object: Assimp makes one aiMesh with mixed
  // faces; the importer makes a TRIANGLES, a LINES and a POINTS primitive.
  const std::string path = TempPath("mixed.obj");
  WriteText(path,
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 2 0\n"
            "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
            "f 1/1 2/2 3/3 4/4\nl 1 3\np 5\n");
  Asset asset;
  const Status s = ImportAssimp(path, &asset);
  fs::remove(path);
  INFO(s.message());
  REQUIRE(s.ok());
  REQUIRE(asset.meshes.size() == 1);
  const std::vector<AssetPrimitive>& prims = asset.meshes[0].primitives;
  REQUIRE(prims.size() == 3);
  CHECK(prims[0].mode == PrimitiveMode::kTriangles);
  CHECK(prims[0].indices.size() == 6);
  REQUIRE(prims[0].texcoords.size() == 1);
  for (std::size_t v = 0; v < prims[0].positions.size(); ++v) {
    // OBJ's vt has v up from the bottom; glTF's v runs down from the top: v' = 1 - v.
    const glm::vec3 p = prims[0].positions[v];
    CHECK(prims[0].texcoords[0][v].x == Approx(p.x));
    CHECK(prims[0].texcoords[0][v].y == Approx(1.0f - p.y));
  }
  CHECK(prims[1].mode == PrimitiveMode::kLines);
  REQUIRE(prims[1].indices.size() == 2);
  const glm::vec3 a = prims[1].positions[prims[1].indices[0]];
  const glm::vec3 b = prims[1].positions[prims[1].indices[1]];
  CHECK(a == glm::vec3(0, 0, 0));
  CHECK(b == glm::vec3(1, 1, 0));
  CHECK(prims[2].mode == PrimitiveMode::kPoints);
  REQUIRE(prims[2].positions.size() == 1);
  CHECK(prims[2].positions[0] == glm::vec3(2, 2, 0));
}

TEST_CASE("ImportAssimp gives a node with several meshes one child per mesh", "[assimp]") {
  // Two materials in one OBJ object: Assimp makes one node listing two aiMeshes.
  const std::string obj = TempPath("two.obj");
  const std::string mtl = TempPath("two.mtl");
  WriteText(mtl, "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n");
  WriteText(obj, ("mtllib " + fs::path(mtl).filename().string() +
                  "\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\no thing\nusemtl red\nf 1 2 3\n"
                  "usemtl blue\nf 1 3 4\n")
                     .c_str());
  Asset asset;
  const Status s = ImportAssimp(obj, &asset);
  fs::remove(obj);
  fs::remove(mtl);
  INFO(s.message());
  REQUIRE(s.ok());
  REQUIRE(asset.meshes.size() == 2);
  const Index thing = NodeByName(asset, "thing");
  REQUIRE(thing != kInvalidIndex);
  const AssetNode& node = asset.nodes[static_cast<std::size_t>(thing)];
  CHECK(node.mesh == kInvalidIndex);
  REQUIRE(node.children.size() == 2);
  for (std::size_t k = 0; k < 2; ++k) {
    const AssetNode& child = asset.nodes[static_cast<std::size_t>(node.children[k])];
    CHECK(child.name == "thing#" + std::to_string(k));
    CHECK(child.mesh == static_cast<Index>(k));
    CHECK(child.parent == thing);
    CHECK_FALSE(child.has_matrix);
    CHECK(child.translation == glm::dvec3(0.0));
  }
  const AssetPrimitive& red = asset.meshes[0].primitives[0];
  REQUIRE(red.material != kInvalidIndex);
  const AssetMaterial& material = asset.materials[static_cast<std::size_t>(red.material)];
  CHECK(material.name == "red");
  CHECK(material.json.find("\"baseColorFactor\":[1,0,0,1]") != std::string::npos);
}

// --- A skinned, animated scene built in code, written as COLLADA by Assimp's exporter. ---

aiNode* MakeNode(const char* name, const aiVector3D& translation) {
  auto* node = new aiNode(name);
  aiMatrix4x4::Translation(translation, node->mTransformation);
  return node;
}

void AddChildren(aiNode* parent, std::vector<aiNode*> children) {
  parent->mNumChildren = static_cast<unsigned>(children.size());
  parent->mChildren = new aiNode*[children.size()];
  for (std::size_t i = 0; i < children.size(); ++i) {
    parent->mChildren[i] = children[i];
    children[i]->mParent = parent;
  }
}

// Six vertices in two rows of a 1 x 2 strip, four triangles. Bones "Hip" at (0, 0.5, 0) and its
// child "Knee" 1 above it. Weights: row y=0 Hip 1; row y=1 Hip 0.5 + Knee 0.5; row y=2 Knee 0.6 +
// Hip 0.2 (sum 0.8: the importer renormalises to 0.75 / 0.25). Clip "Bend": Knee
// rotates from identity (0 s) to 90 degrees about z (1 s) and stays there until 2 s.
aiScene* MakeSkinnedScene() {
  auto* scene = new aiScene();
  scene->mRootNode = new aiNode("Root");
  aiNode* body = MakeNode("Body", aiVector3D(0, 0, 0));
  aiNode* hip = MakeNode("Hip", aiVector3D(0, 0.5f, 0));
  aiNode* knee = MakeNode("Knee", aiVector3D(0, 1, 0));
  AddChildren(scene->mRootNode, {body, hip});
  AddChildren(hip, {knee});
  body->mNumMeshes = 1;
  body->mMeshes = new unsigned[1]{0};

  auto* material = new aiMaterial();
  const aiString material_name("Skin");
  material->AddProperty(&material_name, AI_MATKEY_NAME);
  const aiColor3D diffuse(0.8f, 0.2f, 0.1f);
  material->AddProperty(&diffuse, 1, AI_MATKEY_COLOR_DIFFUSE);
  scene->mNumMaterials = 1;
  scene->mMaterials = new aiMaterial* [1] { material };

  auto* mesh = new aiMesh();
  mesh->mName = aiString("Strip");
  mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  mesh->mNumVertices = 6;
  mesh->mVertices = new aiVector3D[6];
  mesh->mNormals = new aiVector3D[6];
  for (unsigned v = 0; v < 6; ++v) {
    mesh->mVertices[v] = aiVector3D(static_cast<float>(v % 2), static_cast<float>(v / 2), 0);
    mesh->mNormals[v] = aiVector3D(0, 0, 1);
  }
  const unsigned tris[4][3] = {{0, 1, 3}, {0, 3, 2}, {2, 3, 5}, {2, 5, 4}};
  mesh->mNumFaces = 4;
  mesh->mFaces = new aiFace[4];
  for (unsigned f = 0; f < 4; ++f) {
    mesh->mFaces[f].mNumIndices = 3;
    mesh->mFaces[f].mIndices = new unsigned[3]{tris[f][0], tris[f][1], tris[f][2]};
  }
  mesh->mMaterialIndex = 0;
  mesh->mNumBones = 2;
  mesh->mBones = new aiBone*[2];
  auto* hip_bone = new aiBone();
  hip_bone->mName = aiString("Hip");
  aiMatrix4x4::Translation(aiVector3D(0, -0.5f, 0), hip_bone->mOffsetMatrix);
  hip_bone->mNumWeights = 6;
  hip_bone->mWeights =
      new aiVertexWeight[6]{{0, 1.0f}, {1, 1.0f}, {2, 0.5f}, {3, 0.5f}, {4, 0.2f}, {5, 0.2f}};
  auto* knee_bone = new aiBone();
  knee_bone->mName = aiString("Knee");
  aiMatrix4x4::Translation(aiVector3D(0, -1.5f, 0), knee_bone->mOffsetMatrix);
  knee_bone->mNumWeights = 4;
  knee_bone->mWeights = new aiVertexWeight[4]{{2, 0.5f}, {3, 0.5f}, {4, 0.6f}, {5, 0.6f}};
  mesh->mBones[0] = hip_bone;
  mesh->mBones[1] = knee_bone;
  scene->mNumMeshes = 1;
  scene->mMeshes = new aiMesh* [1] { mesh };

  auto* anim = new aiAnimation();
  anim->mName = aiString("Bend");
  // Assimp 5.2's COLLADA exporter writes key times in ticks as if they were seconds (and its
  // reader gives them back at 1000 ticks per second), so this scene counts in seconds.
  anim->mTicksPerSecond = 1.0;
  anim->mDuration = 2.0;
  auto* channel = new aiNodeAnim();
  channel->mNodeName = aiString("Knee");
  // Assimp's COLLADA exporter bakes keys into matrices and skips channels whose T, R and S
  // key counts differ, so all three have keys at 0, 1 and 2 s.
  channel->mNumPositionKeys = 3;
  channel->mPositionKeys = new aiVectorKey[3]{
      {0.0, aiVector3D(0, 1, 0)}, {1.0, aiVector3D(0, 1, 0)}, {2.0, aiVector3D(0, 1, 0)}};
  const float h = std::sqrt(0.5f);
  channel->mNumRotationKeys = 3;
  channel->mRotationKeys = new aiQuatKey[3]{{0.0, aiQuaternion(1, 0, 0, 0)},
                                            {1.0, aiQuaternion(h, 0, 0, h)},
                                            {2.0, aiQuaternion(h, 0, 0, h)}};
  channel->mNumScalingKeys = 3;
  channel->mScalingKeys = new aiVectorKey[3]{
      {0.0, aiVector3D(1, 1, 1)}, {1.0, aiVector3D(1, 1, 1)}, {2.0, aiVector3D(1, 1, 1)}};
  anim->mNumChannels = 1;
  anim->mChannels = new aiNodeAnim* [1] { channel };
  scene->mNumAnimations = 1;
  scene->mAnimations = new aiAnimation* [1] { anim };
  return scene;
}

// Linear sampling of one channel (slerp for rotations), written here from the glTF rules so
// the test does not depend on SamplePose().
std::vector<float> SampleChannel(const AssetAnimation& anim, Index node, AnimationPath path,
                                 float t) {
  for (const AssetAnimationChannel& ch : anim.channels) {
    if (ch.node != node || ch.path != path) continue;
    const AssetAnimationSampler& s = anim.samplers[static_cast<std::size_t>(ch.sampler)];
    const auto n = static_cast<std::size_t>(s.components);
    std::size_t k = 0;
    while (k + 1 < s.times.size() && s.times[k + 1] <= t) ++k;
    if (k + 1 >= s.times.size() || t <= s.times[0]) {
      const std::size_t at = t <= s.times[0] ? 0 : s.times.size() - 1;
      return {s.values.begin() + static_cast<std::ptrdiff_t>(at * n),
              s.values.begin() + static_cast<std::ptrdiff_t>((at + 1) * n)};
    }
    const float u = (t - s.times[k]) / (s.times[k + 1] - s.times[k]);
    const float* a = &s.values[k * n];
    const float* b = &s.values[(k + 1) * n];
    if (path == AnimationPath::kRotation) {
      const glm::quat qa(a[3], a[0], a[1], a[2]);
      const glm::quat qb(b[3], b[0], b[1], b[2]);
      const glm::quat q = glm::slerp(qa, qb, u);
      return {q.x, q.y, q.z, q.w};
    }
    std::vector<float> out(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = a[i] + u * (b[i] - a[i]);
    return out;
  }
  return {};
}

TEST_CASE("ImportAssimp reads a skinned, animated COLLADA file", "[assimp]") {
  const std::string path = TempPath("skinned.dae");
  {
    aiScene* scene = MakeSkinnedScene();
    Assimp::Exporter exporter;
    const aiReturn r = exporter.Export(scene, "collada", path);
    delete scene;
    INFO(exporter.GetErrorString());
    REQUIRE(r == aiReturn_SUCCESS);
  }
  Asset asset;
  const Status s = ImportAssimp(path, &asset);
  fs::remove(path);
  INFO(s.message());
  REQUIRE(s.ok());
  CHECK(asset.source == path);

  // Hierarchy: Root -> {Body, Hip -> Knee}; Hip at (0, 0.5, 0) and Knee at (0, 1, 0) as TRS.
  const Index root = NodeByName(asset, "Root");
  const Index hip = NodeByName(asset, "Hip");
  const Index knee = NodeByName(asset, "Knee");
  REQUIRE(hip != kInvalidIndex);
  REQUIRE(knee != kInvalidIndex);
  CHECK(asset.nodes[static_cast<std::size_t>(knee)].parent == hip);
  REQUIRE(root == 0);
  CHECK(asset.nodes[static_cast<std::size_t>(hip)].parent == root);
  const AssetNode& hip_node = asset.nodes[static_cast<std::size_t>(hip)];
  CHECK_FALSE(hip_node.has_matrix);
  CHECK(hip_node.translation.y == Approx(0.5).margin(1e-6));
  CHECK(std::abs(hip_node.rotation.w) == Approx(1.0).margin(1e-6));
  CHECK(hip_node.scale.x == Approx(1.0).margin(1e-6));
  CHECK(asset.nodes[static_cast<std::size_t>(knee)].translation.y == Approx(1.0).margin(1e-6));

  // One mesh drawn by one node with one skin of two joints.
  REQUIRE(asset.meshes.size() == 1);
  REQUIRE(asset.meshes[0].primitives.size() == 1);
  const AssetPrimitive& prim = asset.meshes[0].primitives[0];
  CHECK(prim.mode == PrimitiveMode::kTriangles);
  REQUIRE(prim.positions.size() == 6);
  CHECK(prim.indices.size() == 12);
  REQUIRE(asset.skins.size() == 1);
  const AssetSkin& skin = asset.skins[0];
  REQUIRE(skin.joints.size() == 2);
  Index drawer = kInvalidIndex;
  for (std::size_t i = 0; i < asset.nodes.size(); ++i)
    if (asset.nodes[i].mesh == 0) drawer = static_cast<Index>(i);
  REQUIRE(drawer != kInvalidIndex);
  CHECK(asset.nodes[static_cast<std::size_t>(drawer)].skin == 0);

  // Inverse bind matrices: translations by -(world bind position) of each bone.
  std::map<Index, int> joint_of;  // node -> joint slot
  for (std::size_t j = 0; j < 2; ++j) {
    joint_of[skin.joints[j]] = static_cast<int>(j);
    const float expected = skin.joints[j] == hip ? -0.5f : -1.5f;
    const glm::mat4& ibm = skin.inverse_bind_matrices[j];
    CHECK(ibm[3][1] == Approx(expected).margin(1e-6));
    CHECK(ibm[3][0] == Approx(0.0).margin(1e-6));
    CHECK(ibm[0][0] == Approx(1.0).margin(1e-6));
    CHECK(ibm[1][1] == Approx(1.0).margin(1e-6));
  }
  REQUIRE(joint_of.count(hip) == 1);
  REQUIRE(joint_of.count(knee) == 1);

  // Influences: one set of 4, sorted by weight, renormalised.
  REQUIRE(prim.joints.size() == 1);
  REQUIRE(prim.weights.size() == 1);
  for (std::size_t v = 0; v < prim.positions.size(); ++v) {
    const glm::vec3 p = prim.positions[v];
    INFO("vertex at " << p.x << " " << p.y << " " << p.z);
    const glm::u16vec4 jn = prim.joints[0][v];
    const glm::vec4 w = prim.weights[0][v];
    CHECK(w.x + w.y + w.z + w.w == Approx(1.0f).margin(1e-6));
    CHECK(w.z == 0.0f);
    CHECK(w.w == 0.0f);
    const int row = static_cast<int>(std::lround(p.y));
    if (row == 0) {
      CHECK(jn.x == joint_of[hip]);
      CHECK(w.x == Approx(1.0f));
      CHECK(w.y == 0.0f);
    } else if (row == 1) {
      CHECK(w.x == Approx(0.5f));
      CHECK(w.y == Approx(0.5f));
      CHECK(jn.x != jn.y);
    } else {
      CHECK(jn.x == joint_of[knee]);
      CHECK(jn.y == joint_of[hip]);
      CHECK(w.x == Approx(0.75f).margin(1e-6));
      CHECK(w.y == Approx(0.25f).margin(1e-6));
    }
  }

  // The material's diffuse colour becomes the glTF base colour.
  REQUIRE(prim.material != kInvalidIndex);
  const AssetMaterial& material = asset.materials[static_cast<std::size_t>(prim.material)];
  CHECK(material.json.find("\"baseColorFactor\":[0.800000012,0.200000003,0.100000001,1]") !=
        std::string::npos);

  // The clip: 2 s long (2000 ticks at 1000 ticks/s in Assimp); Knee at 45 degrees at 0.5 s.
  REQUIRE(asset.animations.size() == 1);
  const AssetAnimation& anim = asset.animations[0];
  CHECK(anim.Duration() == Approx(2.0).margin(1e-6));
  const std::vector<float> q = SampleChannel(anim, knee, AnimationPath::kRotation, 0.5f);
  REQUIRE(q.size() == 4);
  const float half = static_cast<float>(3.14159265358979323846 / 8.0);  // half of 45 degrees
  const float sign = q[3] < 0.0f ? -1.0f : 1.0f;
  CHECK(sign * q[0] == Approx(0.0f).margin(1e-5));
  CHECK(sign * q[1] == Approx(0.0f).margin(1e-5));
  CHECK(sign * q[2] == Approx(std::sin(half)).margin(1e-5));
  CHECK(sign * q[3] == Approx(std::cos(half)).margin(1e-5));
  const std::vector<float> q_end = SampleChannel(anim, knee, AnimationPath::kRotation, 1.5f);
  REQUIRE(q_end.size() == 4);
  CHECK(std::abs(q_end[2]) == Approx(std::sqrt(0.5f)).margin(1e-5));
  const std::vector<float> t = SampleChannel(anim, knee, AnimationPath::kTranslation, 0.7f);
  if (!t.empty()) CHECK(t[1] == Approx(1.0f).margin(1e-6));
}

// --- Assimp reading the .glb files ExportGltf writes. ---

// Imports `source` with ImportGltf, exports it with ExportGltf to a temporary .glb and checks
// what Assimp makes of that file against the asset (test::CheckAssimpReads).
void CheckAssimpReadsExportedGlb(const std::string& source) {
  INFO(source);
  Asset asset;
  Status s = ImportGltf(source, &asset);
  INFO(s.message());
  REQUIRE(s.ok());
  const std::string glb = TempPath(fs::path(source).stem().string() + ".glb");
  s = ExportGltf(asset, GltfExportOptions{}, glb);
  INFO(s.message());
  REQUIRE(s.ok());
  test::CheckAssimpReads(glb, asset);
  fs::remove(glb);
}

TEST_CASE("Assimp reads the .glb files ExportGltf writes", "[assimp][gltf]") {
  if (!HaveData()) {
    WARN("skipped: ../shared/data is absent");
    return;
  }
  for (const char* name :
       {"SimpleSkin.gltf", "RiggedSimple.glb", "RiggedFigure.glb", "Fox.glb", "CesiumMan.glb"}) {
    CheckAssimpReadsExportedGlb(std::string(kData) + "/gltf/" + name);
  }
}

}  // namespace
}  // namespace dermis

namespace dermis {
namespace {

// Assimp 5.2 and the compressed exports (docs/gltf-compression.md, "Who reads what"): it
// reads --quantize files (KHR_mesh_quantization) and refuses --compress files
// (EXT_meshopt_compression is required and it has no decoder) with an error, never garbage.
TEST_CASE("Assimp reads --quantize exports and refuses --compress ones cleanly",
          "[assimp][gltf][compression][data]") {
  const std::string source = "../shared/data/gltf/CesiumMan.glb";
  if (!fs::exists(source)) {
    WARN("skipped: " << source << " is absent (../shared/data)");
    return;
  }
  Asset asset;
  REQUIRE(ImportGltf(source, &asset).ok());
  const std::string dir = fs::temp_directory_path().string() + "/dermis_assimp_compression_" +
                          std::to_string(::getpid());
  fs::create_directories(dir);
  GltfExportOptions options;
  options.quantize = true;
  REQUIRE(ExportGltf(asset, options, dir + "/quantized.glb").ok());
  Asset back;
  REQUIRE(ImportGltf(dir + "/quantized.glb", &back).ok());
  test::CheckAssimpReads(dir + "/quantized.glb", back);

  options.compress = true;
  REQUIRE(ExportGltf(asset, options, dir + "/compressed.glb").ok());
  test::AssimpCounts counts;
  std::string error;
  CHECK_FALSE(test::ReadWithAssimp(dir + "/compressed.glb", &counts, &error));
  INFO(error);
  CHECK_FALSE(error.empty());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace dermis

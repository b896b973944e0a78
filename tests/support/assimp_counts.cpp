// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "support/assimp_counts.h"

#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <catch2/catch.hpp>
#include <vector>

namespace dermis {
namespace test {
namespace {

unsigned CountNodes(const aiNode* node) {
  unsigned n = 1;
  for (unsigned c = 0; c < node->mNumChildren; ++c) n += CountNodes(node->mChildren[c]);
  return n;
}

}  // namespace

bool ReadWithAssimp(const std::string& path, AssimpCounts* counts, std::string* error) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, 0);
  if (scene == nullptr || scene->mRootNode == nullptr) {
    *error = importer.GetErrorString();
    return false;
  }
  counts->meshes = scene->mNumMeshes;
  counts->animations = scene->mNumAnimations;
  counts->nodes = CountNodes(scene->mRootNode);
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    for (unsigned b = 0; b < scene->mMeshes[m]->mNumBones; ++b) {
      counts->bones.insert(scene->mMeshes[m]->mBones[b]->mName.C_Str());
    }
  }
  return true;
}

void CheckAssimpReads(const std::string& gltf, const Asset& asset) {
  INFO(gltf);
  AssimpCounts counts;
  std::string error;
  const bool read = ReadWithAssimp(gltf, &counts, &error);
  INFO(error);
  REQUIRE(read);

  std::size_t primitives = 0;
  for (const AssetMesh& mesh : asset.meshes) primitives += mesh.primitives.size();
  std::set<std::string> joint_names;
  for (const AssetSkin& skin : asset.skins) {
    for (const Index j : skin.joints) {
      const std::string& name = asset.nodes[static_cast<std::size_t>(j)].name;
      joint_names.insert(name.empty() ? "nodes[" + std::to_string(j) + "]" : name);
    }
  }
  REQUIRE(asset.default_scene != kInvalidIndex);
  const AssetScene& scene = asset.scenes[static_cast<std::size_t>(asset.default_scene)];
  std::size_t reachable = 0;
  std::vector<Index> stack(scene.nodes.begin(), scene.nodes.end());
  while (!stack.empty()) {
    const Index n = stack.back();
    stack.pop_back();
    ++reachable;
    for (const Index c : asset.nodes[static_cast<std::size_t>(n)].children) stack.push_back(c);
  }

  CHECK(counts.meshes == primitives);
  CHECK(counts.bones == joint_names);
  CHECK(counts.animations == asset.animations.size());
  CHECK(counts.nodes == reachable + (scene.nodes.size() > 1 ? 1 : 0));
}

}  // namespace test
}  // namespace dermis

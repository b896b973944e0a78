// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Test support: what Assimp 5.2 reads from a glTF file (read with Assimp directly, never
// through ImportAssimp), compared with what it should read for the asset that was written.
// Compile this into the test executable that links dermis::gltf before dermis::assimp.
#pragma once

#include <set>
#include <string>

#include "dermis/asset/asset.h"

namespace dermis {
namespace test {

/// Counts of an aiScene.
struct AssimpCounts {
  unsigned meshes = 0;
  unsigned animations = 0;
  unsigned nodes = 0;
  std::set<std::string> bones;
};

/// Reads `path` with Assimp (no post-processing). False with `error` set if Assimp fails.
bool ReadWithAssimp(const std::string& path, AssimpCounts* counts, std::string* error);

/// Reads `gltf` with Assimp and CHECKs its counts against `asset` (what was written there):
/// - meshes: Assimp makes one aiMesh per glTF primitive, so the total primitive count;
/// - bones: the union of bone names is the set of names of the skins' joints, where Assimp
///   names an unnamed node by its glTF id "nodes[i]" (ExportGltf keeps the node order);
/// - animations: one aiAnimation per clip;
/// - nodes: Assimp walks the default scene. With one root node that node is Assimp's root;
///   with several it adds a "ROOT" node above them. So the count is the nodes reachable from
///   the scene's roots, plus 1 when there is more than one root.
void CheckAssimpReads(const std::string& gltf, const Asset& asset);

}  // namespace test
}  // namespace dermis

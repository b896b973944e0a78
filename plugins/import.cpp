// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/plugins/import.h"

#include "dermis/core/path.h"
#include "dermis/plugins/assimp.h"
#include "dermis/plugins/gltf.h"

namespace dermis {
bool IsGltfPath(const std::string& path) {
  const std::string ext = LowerExtension(path);
  return ext == ".gltf" || ext == ".glb";
}

Status ImportAsset(const std::string& path, Asset* out, std::string* dsurf_bytes) {
  if (IsGltfPath(path)) return ImportGltf(path, out, dsurf_bytes);
  if (dsurf_bytes != nullptr) dsurf_bytes->clear();
  return ImportAssimp(path, out);
}

}  // namespace dermis

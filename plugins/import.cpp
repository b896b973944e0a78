// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/plugins/import.h"

#include <cctype>

#include "dermis/plugins/assimp.h"
#include "dermis/plugins/gltf.h"

namespace dermis {
namespace {

std::string LowerExtension(const std::string& path) {
  const std::size_t slash = path.find_last_of("/\\");
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string ext = path.substr(dot);
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace

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

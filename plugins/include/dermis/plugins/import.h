// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief One entry point for every importer: glTF (.gltf, .glb) goes to tinygltf, everything
/// else to Assimp.
#pragma once

#include <string>

#include "dermis/asset/asset.h"
#include "dermis/core/status.h"

namespace dermis {

/// True for the extensions that ImportGltf() reads (case-insensitive .gltf / .glb).
bool IsGltfPath(const std::string& path);

/// Imports any supported file; `dsurf_bytes` as in ImportGltf() (always empty for Assimp).
Status ImportAsset(const std::string& path, Asset* out, std::string* dsurf_bytes = nullptr);

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Import of FBX, COLLADA, OBJ, PLY and every other format Assimp 5.2 reads into the
/// neutral asset module (meshes, materials, node hierarchy, skins, animations). Never used
/// for glTF, which tinygltf owns (Assimp 5.2 misreads normalised weights and quantised
/// positions, docs/notes/gltf-importers.md).
#pragma once

#include <string>

#include "dermis/asset/asset.h"
#include "dermis/asset/importer.h"
#include "dermis/core/status.h"

namespace dermis {

/// Reads `path` with Assimp into `out`. Animation times are converted from ticks to seconds,
/// bone offset matrices become inverse bind matrices, influences are kept as they are (sets
/// of 4) and renormalised. Errors name the file and carry Assimp's message.
Status ImportAssimp(const std::string& path, Asset* out);

namespace plugins::assimp {
/// Adds the Assimp importer to `registry`: assets from every file that is not glTF (.gltf and
/// .glb are refused), recognised by Assimp by extension or content. Register it last.
void Register(ImporterRegistry* registry);
}  // namespace plugins::assimp

}  // namespace dermis

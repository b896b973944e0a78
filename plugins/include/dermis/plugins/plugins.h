// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Both file-format plugins at once (target dermis::plugins).
#pragma once

#include "dermis/asset/importer.h"
#include "dermis/plugins/assimp.h"
#include "dermis/plugins/gltf.h"

namespace dermis::plugins {

/// Adds the glTF importer, then the Assimp importer (which takes every file that is not glTF,
/// so register scan importers that must win .obj or .ply before it when a tool asks the
/// registry for assets and scans alike).
void Register(ImporterRegistry* registry);

}  // namespace dermis::plugins

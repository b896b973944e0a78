// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The importers of the dermis tool: every subcommand that reads a file other than a .dsurf picks
// its importer from this registry (docs/overview.md, "A new importer").
#pragma once

#include "dermis/asset/importer.h"

namespace dermis::cli {

/// The tool's registry, filled on first use: the OBJ and PLY scan importers, then the glTF
/// and Assimp asset importers (Assimp last: it takes every file that is not glTF).
const ImporterRegistry& Importers();

}  // namespace dermis::cli

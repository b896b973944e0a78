// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The OBJ and PLY readers as importers of scans (dermis/asset/importer.h).
#pragma once

#include "dermis/asset/importer.h"

namespace dermis::io {

/// Adds the OBJ importer (.obj: ReadObj, faces optional) and the PLY importer (.ply: ReadPly)
/// to `registry`, in that order. Both read scans only; assets of those formats are Assimp's.
void Register(ImporterRegistry* registry);

}  // namespace dermis::io

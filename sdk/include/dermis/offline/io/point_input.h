// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Reading the data of a fit: a dense mesh or a point cloud, through a scan importer.
#pragma once

#include <string>

#include "dermis/asset/importer.h"
#include "dermis/core/status.h"
#include "dermis/offline/geometry/polygon_mesh.h"

namespace dermis {

/// Reads the scan at `path` into `mesh` with the scan importer `importers` picks for it (null:
/// the OBJ and PLY importers, io::Register()). Vertices that no face uses are removed when the
/// file has faces, and counted in *dropped; a file without faces is a point cloud and keeps
/// every vertex. Fails, naming the file, if it cannot be read, no importer takes it, it has no
/// vertices or it has a non-finite coordinate.
Status ReadFitInput(const std::string& path, PolygonMesh* mesh, Index* dropped,
                    const ImporterRegistry* importers = nullptr);

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Reading the data of a fit: a dense mesh or a point cloud from OBJ or PLY.
#pragma once

#include <string>

#include "dermis/core/status.h"
#include "dermis/offline/geometry/polygon_mesh.h"

namespace dermis {

/// Reads an .obj or .ply file (chosen by extension, case-insensitive) into `mesh`. Vertices
/// that no face uses are removed when the file has faces, and counted in *dropped; a file
/// without faces is a point cloud and keeps every vertex. Fails, naming the file, if it cannot
/// be read, has an unsupported extension, has no vertices or has a non-finite coordinate.
Status ReadFitInput(const std::string& path, PolygonMesh* mesh, Index* dropped);

}  // namespace dermis

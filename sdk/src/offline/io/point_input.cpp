// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Fit input: OBJ or PLY, a mesh or a point cloud (paper section 4 fits point clouds).
#include "dermis/offline/io/point_input.h"

#include <cmath>

#include "dermis/core/path.h"
#include "dermis/offline/io/obj_io.h"
#include "dermis/offline/io/ply_io.h"

namespace dermis {

Status ReadFitInput(const std::string& path, PolygonMesh* mesh, Index* dropped) {
  const std::string ext = LowerExtension(path);
  Status s;
  if (ext == ".obj") {
    s = ReadObj(path, mesh, /*require_faces=*/false);
  } else if (ext == ".ply") {
    s = ReadPly(path, mesh);
  } else {
    return Status::Unsupported(path + ": unsupported file type '" + (ext.empty() ? "." : ext) +
                               "' (use .obj or .ply; import other formats with the plugins)");
  }
  if (!s.ok()) return s;
  *dropped = 0;
  if (mesh->positions.empty())
    return Status::InvalidInput(path + ": no vertices (empty point cloud)");
  if (mesh->num_faces() > 0) *dropped = CompactUnusedVertices(mesh);
  return Status::Ok();
}

}  // namespace dermis

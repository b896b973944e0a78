// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Fit input: a scan, a mesh or a point cloud (paper section 4 fits point clouds).
#include "dermis/offline/io/point_input.h"

#include "dermis/offline/geometry/polygon_mesh.h"
#include "dermis/offline/io/scan_importers.h"

namespace dermis {

Status ReadFitInput(const std::string& path, PolygonMesh* mesh, Index* dropped,
                    const ImporterRegistry* importers) {
  ImporterRegistry defaults;
  if (importers == nullptr) {
    io::Register(&defaults);
    importers = &defaults;
  }
  const Status s = importers->ImportScan(path, mesh);
  if (!s.ok()) return s;
  *dropped = 0;
  if (mesh->positions.empty())
    return Status::InvalidInput(path + ": no vertices (empty point cloud)");
  const Status range = CheckCoordinateRange(*mesh);
  if (!range.ok()) return range;
  if (mesh->num_faces() > 0) *dropped = CompactUnusedVertices(mesh);
  return Status::Ok();
}

}  // namespace dermis

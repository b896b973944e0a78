// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Fit input: a scan, a mesh or a point cloud (paper section 4 fits point clouds).
#include "dermis/offline/io/point_input.h"

#include <cmath>

#include "dermis/core/limits.h"
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
  for (size_t v = 0; v < mesh->positions.size(); ++v) {
    const Vec3& p = mesh->positions[v];
    if (!(std::abs(p.x) <= limits::kMaxCoordinate && std::abs(p.y) <= limits::kMaxCoordinate &&
          std::abs(p.z) <= limits::kMaxCoordinate)) {
      return Status::InvalidInput(path + ": " + mesh->VertexName(static_cast<Index>(v)) +
                                  " has a non-finite coordinate or one of magnitude above 1e12 "
                                  "(rescale the model)");
    }
  }
  if (mesh->num_faces() > 0) *dropped = CompactUnusedVertices(mesh);
  return Status::Ok();
}

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/offline/geometry/polygon_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dermis/core/limits.h"
#include "dermis/core/mesh_topology.h"

namespace dermis {

Status ValidatePolygonMesh(const PolygonMesh& mesh) {
  const std::string where = mesh.source_name.empty() ? "mesh" : mesh.source_name;
  if (mesh.positions.empty()) return Status::InvalidInput(where + ": no vertices");
  if (mesh.num_faces() <= 0) return Status::InvalidInput(where + ": no faces");
  for (Index v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3& p = mesh.positions[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      return Status::InvalidInput(where + ": " + mesh.VertexName(v) +
                                  " has a non-finite coordinate");
    }
  }
  ElementNamer namer;
  namer.face = [&mesh](Index f) { return mesh.FaceName(f); };
  namer.vertex = [&mesh](Index v) { return mesh.VertexName(v); };
  MeshTopology topo;
  Status s = MeshTopology::Build(mesh.num_vertices(), mesh.face_offsets, mesh.face_vertices, &topo,
                                 &namer);
  if (!s.ok()) return s.WithContext(where);
  for (Index v = 0; v < topo.num_vertices(); ++v) {
    const int k = topo.valence(v);
    if (k > 0 && k < 3 && !topo.is_boundary_vertex(v)) {
      return Status::InvalidInput(where + ": " + mesh.VertexName(v) + " is an interior vertex of " +
                                  std::to_string(k) +
                                  " faces (at least 3 needed: two faces glued along two edges)");
    }
  }
  return Status::Ok();
}

Status CheckCoordinateRange(const PolygonMesh& mesh) {
  const std::string where = mesh.source_name.empty() ? "mesh" : mesh.source_name;
  for (Index v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3& p = mesh.positions[v];
    if (!(std::abs(p.x) <= limits::kMaxCoordinate && std::abs(p.y) <= limits::kMaxCoordinate &&
          std::abs(p.z) <= limits::kMaxCoordinate)) {
      return Status::InvalidInput(where + ": " + mesh.VertexName(v) +
                                  " has a coordinate that is not finite or of magnitude above "
                                  "1e12 (products of such coordinates overflow; rescale the "
                                  "model)");
    }
  }
  return Status::Ok();
}

Index CompactUnusedVertices(PolygonMesh* mesh, std::vector<Index>* old_to_new) {
  std::vector<Index> map(mesh->positions.size(), kInvalidIndex);
  for (Index v : mesh->face_vertices) {
    if (v >= 0 && static_cast<size_t>(v) < map.size()) map[v] = 0;
  }
  Index next = 0;
  std::vector<Vec3> positions;
  std::vector<int> lines;
  for (size_t v = 0; v < map.size(); ++v) {
    if (map[v] == kInvalidIndex) continue;
    map[v] = next++;
    positions.push_back(mesh->positions[v]);
    if (v < mesh->vertex_lines.size()) lines.push_back(mesh->vertex_lines[v]);
  }
  const Index removed = static_cast<Index>(map.size()) - next;
  if (removed > 0) {
    for (Index& v : mesh->face_vertices) v = map[v];
    mesh->positions = std::move(positions);
    mesh->vertex_lines = std::move(lines);
  }
  if (old_to_new) *old_to_new = std::move(map);
  return removed;
}

double BoundingBoxDiagonal(const std::vector<Vec3>& positions) {
  if (positions.empty()) return 0.0;
  Vec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const Vec3& p : positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const Vec3 d = hi - lo;
  return std::sqrt(glm::dot(d, d));
}

}  // namespace dermis

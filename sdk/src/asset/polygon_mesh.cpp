// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/asset/polygon_mesh.h"

namespace dermis {

void PolygonMesh::AddFace(const std::vector<Index>& vertices) {
  face_vertices.insert(face_vertices.end(), vertices.begin(), vertices.end());
  face_offsets.push_back(static_cast<Index>(face_vertices.size()));
}

std::string PolygonMesh::FaceName(Index f) const {
  std::string s = "face " + std::to_string(f);
  if (static_cast<size_t>(f) < face_lines.size())
    s += " (line " + std::to_string(face_lines[f]) + ")";
  return s;
}

std::string PolygonMesh::VertexName(Index v) const {
  std::string s = "vertex " + std::to_string(v);
  if (static_cast<size_t>(v) < vertex_lines.size()) {
    s += " (line " + std::to_string(vertex_lines[v]) + ")";
  }
  return s;
}

}  // namespace dermis

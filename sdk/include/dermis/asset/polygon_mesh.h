// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief A raw, editable polygon mesh (triangles, quads, n-gons, mixed, or no faces: a point
/// cloud) in double precision, exactly as read from a file: what scan importers (OBJ, PLY)
/// fill. Validation as a control mesh: dermis/offline/geometry/polygon_mesh.h.
#pragma once

#include <string>
#include <vector>

#include "dermis/core/types.h"

namespace dermis {

/// Polygon mesh in CSR form. Face f has vertices face_vertices[face_offsets[f] ..
/// face_offsets[f + 1]), counter-clockwise seen from outside. Positions are in model units.
struct PolygonMesh {
  std::vector<Vec3> positions;
  std::vector<Index> face_offsets{0};  ///< num_faces() + 1 entries, starts at 0.
  std::vector<Index> face_vertices;
  /// Optional: the 1-based source line of each face / vertex (for error messages); either may be
  /// empty.
  std::vector<int> face_lines;
  std::vector<int> vertex_lines;
  /// Name of the source (file path) used as the prefix of error messages; may be empty.
  std::string source_name;

  Index num_vertices() const { return static_cast<Index>(positions.size()); }
  Index num_faces() const { return static_cast<Index>(face_offsets.size()) - 1; }
  Index face_size(Index f) const { return face_offsets[f + 1] - face_offsets[f]; }
  /// Appends a face with the given vertex indices.
  void AddFace(const std::vector<Index>& vertices);

  /// "face 3 (line 17)" or "face 3".
  std::string FaceName(Index f) const;
  /// "vertex 5 (line 9)" or "vertex 5" (0-based index).
  std::string VertexName(Index v) const;
};

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Wavefront OBJ reading (polygon control meshes) and writing (tessellated surfaces).
///
/// Why not Assimp: a control mesh must keep its vertices exactly as written (Assimp's OBJ
/// loader splits vertices per face-vertex and may triangulate), and bad input must be reported
/// with its line number. See docs/overview.md, "Hand-written code and why".
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/offline/geometry/polygon_mesh.h"

namespace dermis {

/// Parses OBJ text: `v` (3 coordinates; a 4th weight or colours are ignored), `f` (indices
/// `a`, `a/b`, `a/b/c`, `a//c`, negative = relative), line continuation with a trailing
/// backslash, comments. Other statements (vt, vn, o, g, s, usemtl, mtllib, l, p, ...) are
/// ignored. Errors are "NAME:LINE: problem". Faces are checked for range and repeated
/// indices here; call ValidatePolygonMesh() for manifoldness.
/// A file without faces is an error unless `require_faces` is false (a point cloud).
Status ParseObj(std::string_view text, const std::string& name, PolygonMesh* mesh,
                bool require_faces = true);

/// Reads and parses an OBJ file. An unreadable file gives a kIoError naming the path.
Status ReadObj(const std::string& path, PolygonMesh* mesh, bool require_faces = true);

/// Writes a triangle mesh with per-vertex normals ("v", "vn", "f a//a b//b c//c") to `path`
/// atomically: the file appears complete or not at all. Numbers are written in the shortest
/// form that reads back to the same double. `normals` may be empty.
Status WriteObj(const std::string& path, const std::vector<Vec3>& positions,
                const std::vector<Vec3>& normals, const std::vector<std::uint32_t>& triangles,
                const std::string& header_comment = "");

/// The text WriteObj() writes (for a stream such as stdout); `text` is replaced.
Status FormatObj(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                 const std::vector<std::uint32_t>& triangles, const std::string& header_comment,
                 std::string* text);

/// Writes a polygon mesh (positions and faces) atomically.
Status WritePolygonObj(const std::string& path, const PolygonMesh& mesh);

}  // namespace dermis

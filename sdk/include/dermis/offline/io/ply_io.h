// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Stanford PLY reading (polygon meshes and point sets), ascii and binary.
///
/// Why hand-written: like the OBJ reader, a control mesh must keep its vertices exactly as
/// stored, and bad input must be reported with its line (ascii) or element index (binary)
/// instead of being repaired silently. See docs/overview.md, "Hand-written code and why".
#pragma once

#include <string>
#include <string_view>

#include "dermis/core/status.h"
#include "dermis/offline/geometry/polygon_mesh.h"

namespace dermis {

/// Parses PLY bytes (ascii, binary_little_endian, binary_big_endian; format 1.0) into `mesh`.
///
/// The `vertex` element must have scalar properties x, y and z (any PLY scalar type; they are
/// converted to double exactly); its other properties are skipped. The optional `face` element
/// must have a list property `vertex_indices` (or `vertex_index`) with an integer count and
/// index type; its other properties are skipped. A file without faces is a valid point set.
/// Every other element is skipped. `comment` and `obj_info` header lines are ignored; CRLF line
/// ends are accepted. Data after the last declared element is ignored.
///
/// For ascii files every element is one line and mesh->vertex_lines / face_lines receive the
/// 1-based line numbers; for binary files they are left empty. mesh->source_name = `name`.
///
/// Errors are kInvalidInput with the message "NAME:LINE: problem" for the header and ascii
/// data, and "NAME: ELEMENT INDEX: problem" (e.g. "in.ply: face 7: ...") for binary data. Faces
/// are checked for index range and size (>= 3) here; call ValidatePolygonMesh() for
/// manifoldness. `mesh` is only written on success.
Status ParsePly(std::string_view bytes, const std::string& name, PolygonMesh* mesh);

/// Reads and parses a PLY file; an unreadable file gives kIoError naming the path.
Status ReadPly(const std::string& path, PolygonMesh* mesh);

}  // namespace dermis

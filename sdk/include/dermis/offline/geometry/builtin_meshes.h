// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Built-in control meshes for demos and tests (no external data needed).
#pragma once

#include <string>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/offline/geometry/polygon_mesh.h"

namespace dermis {

/// Names accepted by MakeBuiltinMesh():
/// - "cube": 8 valence-3 vertices, 6 quads;
/// - "tetrahedron", "octahedron": triangles (split into quads);
/// - "torus": 8 x 6 quads, genus 1, all valence 4;
/// - "prismN" (N = 3..64): N-gon prism, caps are N-gons, so the split mesh has valence-N vertices;
/// - "grid": 4 x 3 open quad grid with a boundary, slightly bent;
/// - "house": a cube with a pyramid roof (quads and triangles mixed);
std::vector<std::string> BuiltinMeshNames();

/// Fills `mesh` with the named built-in mesh; its source_name is "builtin:NAME".
Status MakeBuiltinMesh(const std::string& name, PolygonMesh* mesh);

}  // namespace dermis

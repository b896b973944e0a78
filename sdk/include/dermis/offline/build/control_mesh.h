// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Automatic all-quad control mesh from a dense triangle mesh (paper section 4,
/// "Control mesh").
#pragma once

#include "dermis/core/status.h"
#include "dermis/offline/geometry/polygon_mesh.h"

namespace dermis {

/// Options of BuildControlMesh().
struct ControlMeshOptions {
  /// Wanted number of control (quad) vertices. The result is the closest count found.
  int target_vertices = 540;
  /// True: a target above the full split (every usable triangle split into three quads) is
  /// lowered to it; false: such a target is an error.
  bool clamp_to_full_split = false;
};

/// What BuildControlMesh() did.
struct ControlMeshInfo {
  int welded_vertices = 0;       ///< Vertices merged because they had identical positions.
  int degenerate_triangles = 0;  ///< Input triangles dropped as degenerate after welding.
  int simplified_vertices = 0;   ///< Vertices of the simplified triangle mesh.
  int simplified_triangles = 0;
  int edge_flips = 0;   ///< Flips that evened out the valences.
  int max_valence = 0;  ///< Largest valence of the resulting quad mesh.
};

/// Builds a control mesh from a polygon mesh (faces are fan-triangulated): welds vertices
/// with identical positions (meshoptimizer's remap), drops degenerate triangles, simplifies to
/// the triangle count whose one-split quad mesh has about `target_vertices` vertices
/// (meshopt_simplify, boundaries may slide along themselves but stay open), evens out valences
/// by edge flips, splits every triangle into three quads and moves the new edge and face points
/// onto the input surface. Boundaries and separate components are kept. The result is an
/// all-quad mesh that passes ValidatePolygonMesh(). Fails with a message naming the mesh if the
/// mesh has too few vertices or the target cannot be met.
Status BuildControlMesh(const PolygonMesh& mesh, const ControlMeshOptions& options,
                        PolygonMesh* control, ControlMeshInfo* info = nullptr);

}  // namespace dermis

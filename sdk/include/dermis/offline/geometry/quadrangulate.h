// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Polygon mesh to all-quad control mesh (one Catmull-Clark style split).
#pragma once

#include <vector>

#include "dermis/core/status.h"
#include "dermis/core/types.h"
#include "dermis/offline/geometry/polygon_mesh.h"

namespace dermis {

/// An all-quad control mesh. The first `num_input_vertices` positions are the input vertices,
/// unchanged and in input order, so the surface that interpolates the control vertices
/// interpolates the input vertices.
struct QuadMesh {
  std::vector<Vec3> positions;
  std::vector<Index> quads;             ///< 4 vertex indices per face, counter-clockwise.
  std::vector<Index> quad_source_face;  ///< Input face of every quad.
  Index num_input_vertices = 0;
  Index num_quads() const { return static_cast<Index>(quads.size() / 4); }
};

/// Converts a validated polygon mesh to quads. An all-quad mesh is kept as is. Otherwise every
/// face is split once, Catmull-Clark style: a face point (the centroid) and edge points (edge
/// midpoints) are added and an n-gon becomes n quads (vertex, edge point, face point, edge
/// point). All faces are split so that edge points are shared with neighbours (no T-junctions).
/// Positions are linear (centroids and midpoints), not Catmull-Clark averages, so the input
/// vertices stay where they are.
Status Quadrangulate(const PolygonMesh& mesh, QuadMesh* out);

/// The same split applied to every face, quads included (a quad becomes 4): face points at
/// [V, V + F), edge points at [V + F, V + F + E) in MeshTopology's edge order.
Status SplitIntoQuads(const PolygonMesh& mesh, QuadMesh* out);

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Quality measures of a triangle mesh: watertightness, the largest dihedral angle and
/// the integral of |mean curvature|.
#pragma once

#include <cstdint>
#include <vector>

#include "dermis/core/types.h"

namespace dermis {

/// Edge and angle statistics of an indexed triangle mesh.
struct TriangleMeshMetrics {
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  std::size_t edges = 0;                 ///< Undirected edges.
  std::size_t boundary_edges = 0;        ///< Edges used by one triangle.
  std::size_t non_manifold_edges = 0;    ///< Edges used by more than two triangles.
  std::size_t misoriented_edges = 0;     ///< Edges whose two triangles traverse it the same way.
  std::size_t degenerate_triangles = 0;  ///< Zero area or repeated index.
  std::size_t unreferenced_vertices = 0;
  /// Largest angle between the normals of two triangles sharing an edge (radians).
  double max_dihedral = 0.0;
  /// True when every edge has exactly two consistently oriented triangles and none is degenerate.
  bool watertight() const {
    return boundary_edges == 0 && non_manifold_edges == 0 && misoriented_edges == 0 &&
           degenerate_triangles == 0 && triangles > 0;
  }
};

/// Computes the metrics of `triangles` (3 indices per triangle) over `positions`.
TriangleMeshMetrics ComputeTriangleMeshMetrics(const std::vector<Vec3>& positions,
                                               const std::vector<std::uint32_t>& triangles);

/// The integral of |mean curvature| over an indexed triangle mesh (3 indices per triangle
/// into `positions`, model units): (1/2) the sum over its edges shared by exactly two
/// triangles of |dihedral angle| x length (Cohen-Steiner and Morvan 2003). Vertices that round
/// to the same point of a grid of spacing `weld` (> 0) are one, so split seams join. Ripples
/// and lumps add to it however small they are: a surface that follows its source's shape
/// gives about the source's (bench_fit's curvature ratio). Degenerate triangles count as
/// flat. Deterministic.
double AbsMeanCurvatureIntegral(const std::vector<Vec3>& positions,
                                const std::vector<std::uint32_t>& triangles, double weld);

}  // namespace dermis

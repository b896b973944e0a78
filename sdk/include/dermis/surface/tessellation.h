// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Uniform tessellation of every control face into an n x n grid, shared samples on
/// edges and vertices evaluated once, so a closed control mesh gives a watertight mesh.
#pragma once

#include <cstdint>
#include <vector>

#include "dermis/core/mesh_topology.h"
#include "dermis/core/status.h"
#include "dermis/surface/displacement.h"
#include "dermis/surface/manifold_domain.h"

namespace dermis {

/// Where a tessellation sample lies: its owning face and face coordinates.
struct SampleLocation {
  Index face = kInvalidIndex;
  double u = 0.0;
  double v = 0.0;
};

/// The topology of a tessellation, independent of positions: built once, evaluated per frame.
///
/// Sample order: one per control vertex (index = vertex), then level - 1 per edge (in edge
/// order, along the edge's canonical half-edge), then (level - 1)^2 per face (row-major in v,
/// then u). Each grid cell is split into two counter-clockwise triangles along the diagonal
/// that points at the cell's nearest face corner, so the pattern is the same whichever corner
/// is corner 0.
struct TessellationPattern {
  int level = 0;
  std::vector<SampleLocation> samples;
  std::vector<std::uint32_t> triangles;  ///< 3 sample indices per triangle.

  /// Builds the pattern for an all-quad topology at `level` >= 1 segments per face edge.
  static Status Build(const MeshTopology& topology, int level, TessellationPattern* out);
};

/// Evaluates samples [0, count) into caller-owned buffers (count positions and count normals;
/// normals may be null). Returns false if any sample location is invalid.
bool EvaluateSamples(const ManifoldDomain& domain, const LocalPatch* patches,
                     const Displacement* displacement, const SampleLocation* samples,
                     std::size_t count, Vec3* positions, Vec3* normals);

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief How noisy a dense mesh's vertex positions are: the leave-one-out distance of a
/// vertex from a quadric fitted to its neighbours (docs/fitting.md, "Noise-adaptive control
/// fit").
#pragma once

#include "dermis/offline/geometry/polygon_mesh.h"

namespace dermis {

/// Result of EstimateVertexNoise().
struct VertexNoise {
  /// Median over the sampled vertices of the distance (model units) between a vertex and the
  /// quadric height field fitted to its two-ring neighbours without it. A smooth surface
  /// sampled exactly gives the quadric's truncation error (fourth order in the spacing); a
  /// scan, its noise.
  double median = 0.0;
  /// Median distance from a sampled vertex to its one-ring neighbours (model units): the
  /// spacing the estimate was made at.
  double spacing = 0.0;
  int vertices_used = 0;  ///< Sampled vertices with enough neighbours for the fit.
};

/// Estimates the noise of `mesh`'s vertex positions at up to `max_samples` vertices spread
/// evenly over its vertex order (deterministic). A vertex needs at least 8 neighbours in its
/// two-ring (boundary vertices of a coarse mesh may not), and one whose neighbourhood has a
/// non-finite position is skipped; with none usable the result is all zeros. Faces of any
/// size; their edges define the rings (indices out of range are ignored).
VertexNoise EstimateVertexNoise(const PolygonMesh& mesh, int max_samples = 2000);

}  // namespace dermis

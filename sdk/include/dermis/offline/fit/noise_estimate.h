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
  /// sampled exactly gives the quadric's truncation error: third order in the spacing on
  /// irregular neighbourhoods, fourth on symmetric ones; a scan, its noise.
  double median = 0.0;
  /// Median over the sampled vertices of their mean one-ring edge (model units): the spacing
  /// the estimate was made at.
  double spacing = 0.0;
  /// Median over the sampled vertices of distance / mean one-ring edge: the noise relative to
  /// the sampling, which FitSurface reads (FitOptions::control_fit_noisy_ratio). It depends
  /// on the resolution as well as on the noise: a coarse exact tessellation reads noisier
  /// than a fine one, a scan's ratio is its noise over its spacing.
  double median_ratio = 0.0;
  int vertices_used = 0;  ///< Sampled vertices with enough neighbours for the fit.
};

/// Estimates the noise of `mesh`'s vertex positions at up to `max_samples` vertices spread
/// evenly over its vertex order (deterministic; rings are built for those vertices and their
/// neighbours only). A vertex needs at least 8 neighbours in its two-ring, not counting
/// neighbours at its own position (boundary vertices of a coarse mesh may not have them); one
/// whose neighbourhood has a non-finite position is skipped; with none usable the result is
/// all zeros. Faces of any size; their edges define the rings (faces or corners that index
/// out of range are ignored).
VertexNoise EstimateVertexNoise(const PolygonMesh& mesh, int max_samples = 2000);

}  // namespace dermis

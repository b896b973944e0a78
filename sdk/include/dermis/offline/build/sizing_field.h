// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Adaptive target edge length for remeshing: smaller where the surface curves (thin
/// parts: ears, fingers, tails) and along short boundary loops, graded so it never changes
/// abruptly (docs/fitting.md, "Control mesh: sizing").
#pragma once

#include <cstdint>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/core/types.h"
#include "dermis/offline/geometry/triangle_distance.h"

namespace dermis {

/// Options of SizingField.
struct SizingOptions {
  /// Where the surface curves more than the reference curvature kappa_ref (the area-weighted
  /// `reference_quantile` of the curvature over the surface), the size shrinks as
  /// h = h_max (kappa_ref / kappa)^curvature_exponent: with exponent 1, every edge there turns
  /// the normal by about the same angle. Relative, so a fixed vertex budget is shared between
  /// flat and curved parts whatever the model's scale.
  double curvature_exponent = 1.0;
  double reference_quantile = 0.5;
  /// If positive, an absolute bound whatever the budget: h <= max_turn / kappa, so that every
  /// edge turns the normal by at most about this many radians (a thin limb keeps at least
  /// 2 pi / max_turn edges around). Overrides min_fraction.
  double max_turn = 0.0;
  /// The smallest size as a fraction of the largest (h_max): keeps noise and sharp creases
  /// from taking the whole vertex budget.
  double min_fraction = 0.25;
  /// Gradation: the size grows by at most this much per unit of distance (|grad h| <= g).
  double gradation = 0.5;
  /// Each boundary loop gets at least this many edges: h <= loop length / loop_segments.
  int loop_segments = 4;
  /// Radius (model units) over which the curvature is measured; 0: a thousandth of the seed's
  /// bounding-box diagonal. About half the target edge length: finer detail (scan noise, the
  /// seed's own facets) then averages out while thin parts still show.
  double curvature_radius = 0.0;
};

/// A target edge length over a coarse triangle approximation of the surface (the seed of the
/// remesher): curvature per seed vertex, then per-vertex sizes for a given largest size h_max,
/// interpolated at any point through the closest seed triangle. Deterministic; queries are
/// const and thread-safe.
class SizingField {
 public:
  /// Measures the curvature of the seed (positions, triangles: a manifold, consistently
  /// oriented triangle mesh) at each vertex as the largest principal curvature (in magnitude)
  /// of the normal-cycle curvature tensor over the seed within `curvature_radius`: the sum over
  /// those edges of signed dihedral angle x length x (unit direction)(unit direction)^T,
  /// divided by their vertices' area. `vertex_loop_length` gives, per seed vertex, the length
  /// of its boundary loop (0 inside). Fails on empty or mismatched input.
  Status Build(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& triangles,
               const std::vector<double>& vertex_loop_length, const SizingOptions& options);

  /// Sets the largest size and recomputes every seed vertex's size: h_max (kappa_ref /
  /// kappa)^exponent within [min_fraction h_max, h_max], at most loop length / loop_segments,
  /// then graded.
  void SetScale(double h_max);
  double scale() const { return h_max_; }
  /// Vertices an isotropic triangle mesh following the sizes would have: the integral of
  /// 1 / ((sqrt(3) / 2) h^2) over the seed's area.
  double PredictedVertices() const;
  /// Sets (and returns) the h_max whose PredictedVertices() is `vertices` (bisection).
  double SetScaleForVertices(double vertices);
  /// The size at p: interpolated on the closest seed triangle that faces like `normal` (any
  /// closest triangle when `normal` is zero).
  double At(const Vec3& p, const Vec3& normal) const;

  /// Per seed vertex: curvature (1 / model units) and current size (model units).
  const std::vector<double>& curvature() const { return curvature_; }
  /// The reference curvature kappa_ref (1 / model units).
  double reference_curvature() const { return reference_curvature_; }
  const std::vector<double>& sizes() const { return size_; }

 private:
  std::vector<Vec3> positions_;
  std::vector<std::uint32_t> triangles_;
  std::vector<Vec3> normals_;
  std::vector<double> areas_;
  std::vector<double> curvature_, loop_length_, size_;
  std::vector<std::vector<Index>> neighbors_;
  SizingOptions options_;
  double h_max_ = 0.0;
  double reference_curvature_ = 0.0;
  TriangleDistanceTree tree_;
};

}  // namespace dermis

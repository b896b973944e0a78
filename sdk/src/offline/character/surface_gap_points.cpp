// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Points of a character part's source where its fitted surface leaves it: the surface -> source
// half of the two-sided Hausdorff distance (E3, paper section 4's error metrics), sampled per
// control face, turned into data (docs/characters.md, "Where the surface leaves the source").
#include "surface_gap_points.h"

#include "dermis/surface/surface_evaluator.h"

namespace dermis::character {

std::vector<Vec3> SurfaceGapPoints(const FittedSurface& fitted, const TriangleDistanceTree& tree,
                                   const ShadingSurface& shading, double max_distance,
                                   int per_edge) {
  std::vector<Vec3> out;
  if (!(max_distance > 0.0) || per_edge < 1 || !fitted.surface.domain) return out;
  const ManifoldDomain& domain = *fitted.surface.domain;
  for (Index f = 0; f < domain.num_faces(); ++f) {
    for (int i = 0; i < per_edge; ++i) {
      for (int j = 0; j < per_edge; ++j) {
        const Vec2 uv((i + 0.5) / per_edge, (j + 0.5) / per_edge);
        SurfacePoint sp;
        if (!EvaluateSurface(domain, fitted.surface.patches.data(), fitted.displacement.get(), f,
                             uv, &sp)) {
          continue;
        }
        const ClosestPoint cp = tree.Query(sp.position);
        if (cp.triangle == kInvalidIndex) continue;
        const double w[3] = {cp.barycentric.x, cp.barycentric.y, cp.barycentric.z};
        const Vec3 q = shading.Point(cp.triangle, w);
        if (glm::length(q - sp.position) > max_distance) out.push_back(q);
      }
    }
  }
  return out;
}

}  // namespace dermis::character

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The points whose common-displacement solve (paper section 4, docs/notes/fit.md section 4b)
// does not converge keep the projection's parameter, which can be far from where the fitted
// surface passes them: that parameter is the nearest patch's closest point, and beside a
// boundary or a sharp rim the blended surface there is elsewhere. Their parameter becomes the
// closest point of the fitted surface (paper Eq. 4), searched from the nearest sample of a
// grid over the faces around the point as well as from the parameter itself (docs/fitting.md,
// "Points the optimisation loses").
#include "dermis/offline/fit/lost_point_parameters.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dermis/core/parallel.h"
#include "dermis/offline/fit/surface_projection.h"
#include "dermis/surface/manifold_domain.h"
#include "dermis/surface/surface_evaluator.h"

namespace dermis {
namespace {

// The faces within two face rings of `face` (sharing a vertex with a face that shares a vertex
// with it), sorted.
std::vector<Index> FaceNeighbourhood(const MeshTopology& topo, Index face) {
  std::vector<Index> faces = {face};
  for (int ring = 0; ring < 2; ++ring) {
    std::vector<Index> next = faces;
    for (Index f : faces) {
      for (Index k = 0; k < topo.face_size(f); ++k) {
        const Index v = topo.face_vertex(f, static_cast<int>(k));
        for (int i = 0; i < topo.valence(v); ++i) next.push_back(topo.ring(v, i).face);
      }
    }
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    faces = std::move(next);
  }
  return faces;
}

}  // namespace

std::int64_t PlaceLostPoints(const ManifoldDomain& domain, const LocalPatch* patches,
                             const Displacement* displacement, const std::vector<Vec3>& points,
                             std::vector<PointFit>* fits, int level, int threads) {
  if (fits->size() != points.size()) return 0;
  const MeshTopology& topo = domain.topology();
  std::vector<std::size_t> lost;
  for (std::size_t i = 0; i < fits->size(); ++i) {
    const PointFit& f = (*fits)[i];
    const Vec3& p = points[i];
    if (f.status == PointFitStatus::kNotConverged && f.face >= 0 && f.face < topo.num_faces() &&
        std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) {
      lost.push_back(i);
    }
  }
  if (lost.empty()) return 0;
  // Each lost point's neighbourhood, and a grid of (level + 1)^2 samples on every face of them.
  const int n = std::max(level, 1);
  const std::size_t per_face = static_cast<std::size_t>((n + 1) * (n + 1));
  std::vector<std::vector<Index>> around(lost.size());
  std::vector<Index> faces;
  for (std::size_t k = 0; k < lost.size(); ++k) {
    around[k] = FaceNeighbourhood(topo, (*fits)[lost[k]].face);
    faces.insert(faces.end(), around[k].begin(), around[k].end());
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  std::vector<Vec3> grid(faces.size() * per_face);
  std::vector<char> valid(grid.size(), 0);
  const int nthreads = ResolveThreadCount(threads);
  ParallelFor(nthreads, faces.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t q = b; q < e; ++q) {
      for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
          const std::size_t s = q * per_face + static_cast<std::size_t>(j * (n + 1) + i);
          SurfacePoint sp;
          if (EvaluateSurface(domain, patches, displacement, faces[q],
                              Vec2(static_cast<double>(i) / n, static_cast<double>(j) / n), &sp)) {
            grid[s] = sp.position;
            valid[s] = 1;
          }
        }
      }
    }
  });
  std::vector<char> moved(lost.size(), 0);
  ParallelFor(nthreads, lost.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) {
      PointFit& f = (*fits)[lost[k]];
      const Vec3& p = points[lost[k]];
      // Start 1: the fit's own parameter (Gauss-Newton only accepts steps that get closer, so
      // this is never farther than the parameter itself).
      Index best_face = f.face;
      Vec2 best_uv = f.uv;
      double best = ClosestPointOnSurface(domain, patches, displacement, p, &best_face, &best_uv);
      // Start 2: the nearest grid sample around it (the first of equals, in face order).
      double nearest = std::numeric_limits<double>::infinity();
      Index seed_face = kInvalidIndex;
      Vec2 seed_uv(0.0);
      for (Index face : around[k]) {
        const auto q = static_cast<std::size_t>(std::lower_bound(faces.begin(), faces.end(), face) -
                                                faces.begin());
        for (std::size_t s = 0; s < per_face; ++s) {
          if (!valid[q * per_face + s]) continue;
          const Vec3 d = grid[q * per_face + s] - p;
          const double d2 = glm::dot(d, d);
          if (d2 < nearest) {
            nearest = d2;
            seed_face = face;
            seed_uv = Vec2(static_cast<double>(s % static_cast<std::size_t>(n + 1)) / n,
                           static_cast<double>(s / static_cast<std::size_t>(n + 1)) / n);
          }
        }
      }
      if (seed_face != kInvalidIndex) {
        const double d =
            ClosestPointOnSurface(domain, patches, displacement, p, &seed_face, &seed_uv);
        if (d < best) best = d, best_face = seed_face, best_uv = seed_uv;
      }
      ClosestPointAlongBoundary(domain, patches, displacement, p, around[k], &best_face, &best_uv,
                                &best);
      if (best_face != f.face || best_uv != f.uv) {
        f.face = best_face;
        f.uv = best_uv;
        moved[k] = 1;
      }
    }
  });
  std::int64_t count = 0;
  for (char m : moved) count += m;
  return count;
}

}  // namespace dermis

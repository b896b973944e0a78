// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Per-point projection (Yoon section 4, "Initial displacements") and the common-displacement
// optimisation that replaces the paper's Powell search on Eq. 5 (docs/notes/fit.md section 4b).
#include "dermis/offline/fit/point_fit.h"

#include <algorithm>
#include <cmath>

#include "dermis/core/parallel.h"
#include "dermis/offline/fit/surface_projection.h"
#include "dermis/offline/geometry/triangle_distance.h"
#include "dermis/surface/chart.h"

namespace dermis {
namespace {

// Signed distance of p from patch v at z along the patch's unit normal.
double SignedDistance(const LocalPatch& patch, Vec2 z, const Vec3& p) {
  PatchFrame f;
  EvaluatePatchFrame(patch, z, &f);
  return glm::dot(p - f.p, f.n);
}

// The closest control face of a point: each quad as the triangles (0, 1, 2) and (0, 2, 3).
void BuildControlFaceTree(const ManifoldDomain& domain, const std::vector<Vec3>& x,
                          TriangleDistanceTree* tree) {
  std::vector<std::uint32_t> triangles;
  const Index num_faces = domain.num_faces();
  triangles.reserve(static_cast<std::size_t>(num_faces) * 6);
  for (Index f = 0; f < num_faces; ++f) {
    const auto c = [&](int a) {
      return static_cast<std::uint32_t>(domain.topology().face_vertex(f, a));
    };
    triangles.insert(triangles.end(), {c(0), c(1), c(2), c(0), c(2), c(3)});
  }
  tree->Build(x, triangles);
}

// Yoon's projection (paper section 4, "Initial displacements") of point p, then the
// optimisation of Eq. 5 (docs/notes/fit.md section 4b); fills *out.
//
// A solve that converges far from where it started is a spurious root of Q(z) + delta N(z) = p:
// the normal line of some distant part of the surface through p (measured on the bunny with a
// control mesh of 600 vertices: delta = 6 times the scan's size, and the displacement levels
// fitted to it spiked the surface by more than its diagonal). The surface lies within about a
// control face's size of that face, so a root whose |delta| exceeds the start's by more than
// the face's longest edge is not taken: the point counts as not converged.
double LongestEdge(const ManifoldDomain& domain, const std::vector<Vec3>& x, Index face) {
  double longest = 0.0;
  for (int a = 0; a < 4; ++a) {
    const Vec3 e = x[domain.topology().face_vertex(face, a)] -
                   x[domain.topology().face_vertex(face, (a + 1) & 3)];
    longest = std::max(longest, glm::length(e));
  }
  return longest;
}

bool Plausible(double delta, double start_delta, double reach) {
  return std::abs(delta) <= std::abs(start_delta) + reach;
}

// The fit of point p from a start in the chart of vertex v0 (z0; face1, uv1 in face
// coordinates): the other corners' samples, then the optimisation of Eq. 5.
void FitFrom(const ManifoldDomain& domain, const LocalPatch* patches, const std::vector<Vec3>& x,
             const Vec3& p, const PointFitOptions& options, Index v0, Vec2 z0, Index face1,
             Vec2 uv1, PointFit* out) {
  PointFit& r = *out;
  r = PointFit();
  r.projected_face = face1;
  r.projected_uv = uv1;
  r.delta = SignedDistance(patches[v0], z0, p);
  // The other corners: transition, then a few Newton steps on their own patch.
  for (int a = 0; a < 4 && options.chart_samples; ++a) {
    const Index va = domain.topology().face_vertex(face1, a);
    Vec2 za = va == v0 ? z0 : domain.FaceToChart(face1, a, uv1);
    if (va != v0) za = ProjectOntoPatch(patches[va], p, za, 3);
    if (!InsideChart(domain, va, za)) continue;
    r.projected[r.num_projected++] = ChartSample{va, za, SignedDistance(patches[va], za, p)};
  }
  r.status = PointFitStatus::kNotConverged;
  r.face = face1;
  r.uv = uv1;
  if (!options.optimize &&
      !(options.optimize_beside_boundary && domain.topology().face_touches_boundary(face1))) {
    return;
  }
  const CommonDisplacementSolution s =
      SolveCommonDisplacement(domain, patches, p, v0, z0, r.delta, options.tolerance);
  if (!s.converged || !Plausible(s.delta, r.delta, LongestEdge(domain, x, face1))) return;
  r.status = PointFitStatus::kOptimized;
  r.face = s.face;
  r.uv = s.uv;
  r.delta = s.delta;
  const double ub = 1.0 - domain.options().blend_lb;
  for (int a = 0; a < 4; ++a) {
    const Vec2 cd = FaceToCorner(a, s.uv);
    if (cd.x >= ub || cd.y >= ub) continue;
    r.optimized[r.num_optimized++] = ChartSample{domain.topology().face_vertex(s.face, a),
                                                 domain.FaceToChart(s.face, a, s.uv), s.delta};
  }
}

void FitPoint(const ManifoldDomain& domain, const LocalPatch* patches, const std::vector<Vec3>& x,
              const TriangleDistanceTree& tree, const Vec3& p, const PointFitOptions& options,
              PointFit* out) {
  PointFit& r = *out;
  const ClosestPoint cp = tree.Query(p);
  if (cp.triangle == kInvalidIndex) return;
  const Index face = cp.triangle / 2;
  const Vec3& b = cp.barycentric;
  // Face coordinates of the projection on the control face (exact for parallelograms).
  const Vec2 uv0 = (cp.triangle % 2 == 0) ? Vec2(b.y + b.z, b.z) : Vec2(b.y, b.y + b.z);
  // Corners by distance from the projection; the nearest whose patch projection stays in
  // its chart is used (Yoon uses the nearest only; the others rescue points near the edge
  // of a chart's reach).
  int order[4] = {0, 1, 2, 3};
  double dist[4];
  for (int a = 0; a < 4; ++a) {
    const Vec3 d = x[domain.topology().face_vertex(face, a)] - cp.point;
    dist[a] = glm::dot(d, d);
  }
  std::sort(order, order + 4,
            [&](int l, int m) { return dist[l] < dist[m] || (dist[l] == dist[m] && l < m); });
  Index v0 = kInvalidIndex, face1 = kInvalidIndex;
  Vec2 z0, uv1;
  for (int k = 0; k < 4 && v0 == kInvalidIndex; ++k) {
    const int corner = order[k];
    const Index v = domain.topology().face_vertex(face, corner);
    const Vec2 z = ProjectOntoPatch(patches[v], p, domain.FaceToChart(face, corner, uv0), 20);
    if (InsideChart(domain, v, z) && domain.ChartToFace(v, z, &face1, &uv1)) v0 = v, z0 = z;
  }
  if (v0 == kInvalidIndex) {
    // No patch projection stayed in its chart: start the blended solve from the control
    // face.
    const int corner = order[0];
    const Index v = domain.topology().face_vertex(face, corner);
    const Vec2 z = domain.FaceToChart(face, corner, uv0);
    // Without a projection there is no parameter to fall back on: solve whenever the partial
    // solve is on.
    if (!options.optimize && !options.optimize_beside_boundary) return;
    const double start = SignedDistance(patches[v], z, p);
    const CommonDisplacementSolution s =
        SolveCommonDisplacement(domain, patches, p, v, z, start, options.tolerance);
    if (!s.converged || !Plausible(s.delta, start, LongestEdge(domain, x, face))) return;
    const int c = DominantCorner(s.uv);
    v0 = domain.topology().face_vertex(s.face, c);
    z0 = domain.FaceToChart(s.face, c, s.uv);
    face1 = s.face, uv1 = s.uv;
  }
  FitFrom(domain, patches, x, p, options, v0, z0, face1, uv1, out);
  // A root of Q(z) + delta N(z) = p can be a distant part of the surface whose normal line
  // passes through p: the patch projection can end there, on a patch that the point's own
  // part of the surface does not reach (measured beside the cuts of the Fox's control mesh
  // kept along its gentle hard edges: 1.5 to 3.1 model units, where the surface passes within
  // 1e-4). The domain surface lies near its control mesh: an optimised fit further from the
  // point than the closest control face by more than a twentieth of that face starts again
  // from the closest surface point searched from the control face's own parameter and from
  // its centre, and the closer fit is kept. (A point the solve loses is placed later,
  // PlaceLostPoints.)
  if (r.status != PointFitStatus::kOptimized) return;
  const double fitted = std::abs(r.delta);
  if (!(fitted > cp.distance + 0.05 * LongestEdge(domain, x, face))) return;
  Index best_face = kInvalidIndex;
  Vec2 best_uv;
  double best = fitted;
  for (const Vec2& start : {uv0, Vec2(0.5)}) {
    Index f2 = face;
    Vec2 uv2 = start;
    const double d = ClosestPointOnSurface(domain, patches, nullptr, p, &f2, &uv2);
    if (d < best) best = d, best_face = f2, best_uv = uv2;
  }
  if (best_face == kInvalidIndex) return;
  const int c = DominantCorner(best_uv);
  PointFit again;
  FitFrom(domain, patches, x, p, options, domain.topology().face_vertex(best_face, c),
          domain.FaceToChart(best_face, c, best_uv), best_face, best_uv, &again);
  if (again.status == PointFitStatus::kOptimized && std::abs(again.delta) < fitted) r = again;
}

}  // namespace

void FitPoints(const ControlSurface& surface, const std::vector<Vec3>& points,
               const PointFitOptions& options, std::vector<PointFit>* out) {
  const ManifoldDomain& domain = *surface.domain;
  TriangleDistanceTree tree;
  BuildControlFaceTree(domain, surface.control.positions, &tree);
  out->assign(points.size(), PointFit());
  ParallelFor(ResolveThreadCount(options.threads), points.size(),
              [&](std::size_t begin, std::size_t end) {
                for (std::size_t i = begin; i < end; ++i) {
                  FitPoint(domain, surface.patches.data(), surface.control.positions, tree,
                           points[i], options, &(*out)[i]);
                }
              });
}

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Evaluation of the blended surface D(W) = sum_a psi_a(W) S_a(theta(W)) (Yoon Eq. 4) with
// S_a = P_a + d_a N_a (Eq. 3), following docs/notes/manifold.md section 6: corner weights in face
// coordinates, the "one chart" shortcut on [0, lb]^2 and normals from the dominant corner chart.
#include "dermis/surface/surface_evaluator.h"

#include <cmath>

#include "dermis/surface/blend.h"

namespace dermis {
namespace {

Vec3 NormalizeOr(Vec3 n, Vec3 fallback) {
  const double len = std::sqrt(glm::dot(n, n));
  if (len > 0.0 && std::isfinite(len)) return n / len;
  return fallback;
}

}  // namespace

void EvaluateChartSurface(const LocalPatch& patch, const Displacement* displacement, Index vertex,
                          Vec2 z, Vec3* position, Vec3* dx, Vec3* dy) {
  PatchFrame f;
  EvaluatePatchFrame(patch, z, &f);
  double d = 0.0;
  Vec2 g(0.0);
  if (displacement) displacement->Evaluate(vertex, z, &d, &g);
  *position = f.p + d * f.n;
  *dx = f.px + g.x * f.n + d * f.nx;
  *dy = f.py + g.y * f.n + d * f.ny;
}

bool ClampFaceCoordinates(const ManifoldDomain& domain, Index face, Vec2* uv) {
  if (face < 0 || face >= domain.num_faces()) return false;
  const double tol = 1e-12;
  if (!(uv->x >= -tol && uv->x <= 1.0 + tol && uv->y >= -tol && uv->y <= 1.0 + tol)) return false;
  *uv = glm::clamp(*uv, Vec2(0.0), Vec2(1.0));
  return true;
}

bool EvaluateSurface(const ManifoldDomain& domain, const LocalPatch* patches,
                     const Displacement* displacement, Index face, Vec2 uv, SurfacePoint* out) {
  if (!ClampFaceCoordinates(domain, face, &uv)) return false;
  const MeshTopology& topo = domain.topology();
  const Index base = topo.face_offset(face);
  const double lb = domain.options().blend_lb;
  const double ub = 1.0 - lb;
  const BlendType blend = domain.options().blend_type;

  // Dominant corner: the one whose quarter [0, 1/2]^2 of the face holds the point.
  const int dominant = DominantCorner(uv);
  const Vec2 cd_dom = FaceToCorner(dominant, uv);
  SurfacePoint r;
  r.chart_corner = dominant;
  r.chart_vertex = topo.halfedge_origin(base + dominant);

  if (cd_dom.x <= lb && cd_dom.y <= lb) {
    // One chart: psi = 1 here and every other weight and its gradient vanish.
    const Index h = base + dominant;
    const Index v = r.chart_vertex;
    Vec2 z;
    glm::dmat2 jac;
    const bool jac_ok = ChartMap(domain.chart(v), topo.halfedge_ring_index(h), cd_dom, &z, &jac);
    EvaluateChartSurface(patches[v], displacement, v, z, &r.position, &r.dx, &r.dy);
    if (jac_ok) {
      const glm::dmat2 m = jac * FaceToCornerJacobian(dominant);
      r.du = r.dx * m[0].x + r.dy * m[0].y;
      r.dv = r.dx * m[1].x + r.dy * m[1].y;
      r.face_derivatives_valid = true;
    }
    r.normal = NormalizeOr(glm::cross(r.dx, r.dy), patches[v].fallback_normal);
    *out = r;
    return true;
  }

  Vec3 s(0.0), su(0.0), sv(0.0);
  glm::dmat2 m_dom(1.0);
  double weights[4];
  Vec2 weight_gradients[4];
  FaceCornerWeights(blend, lb, uv, weights, weight_gradients);
  for (int a = 0; a < 4; ++a) {
    const Vec2 cd = FaceToCorner(a, uv);
    if (cd.x >= ub || cd.y >= ub) continue;
    const Index h = base + a;
    const Index v = topo.halfedge_origin(h);
    const Vec2 grad_psi = weight_gradients[a];
    const double psi = weights[a];
    Vec2 z;
    glm::dmat2 jac;
    ChartMap(domain.chart(v), topo.halfedge_ring_index(h), cd, &z, &jac);  // r > 0 here
    Vec3 x, xx, xy;
    EvaluateChartSurface(patches[v], displacement, v, z, &x, &xx, &xy);
    const glm::dmat2 d = FaceToCornerJacobian(a);
    const glm::dmat2 m = jac * d;  // columns dz/du, dz/dv
    const Vec3 xu = xx * m[0].x + xy * m[0].y;
    const Vec3 xv = xx * m[1].x + xy * m[1].y;
    const double psi_u = glm::dot(grad_psi, d[0]);
    const double psi_v = glm::dot(grad_psi, d[1]);
    s += psi * x;
    su += psi_u * x + psi * xu;
    sv += psi_v * x + psi * xv;
    if (a == dominant) m_dom = m;
  }
  r.position = s;
  r.du = su;
  r.dv = sv;
  r.face_derivatives_valid = true;
  // Derivatives in the dominant chart: [Sx Sy] = [Su Sv] (dz/duv)^{-1}.
  const glm::dmat2 inv = glm::inverse(m_dom);
  r.dx = su * inv[0].x + sv * inv[0].y;
  r.dy = su * inv[1].x + sv * inv[1].y;
  r.normal = NormalizeOr(glm::cross(r.dx, r.dy), patches[r.chart_vertex].fallback_normal);
  *out = r;
  return true;
}

}  // namespace dermis

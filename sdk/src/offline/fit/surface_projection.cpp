// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Projection of data points onto Yoon's bi-quadratic local patches (paper section 4) and the
// common-displacement Newton solve that replaces the paper's Powell search on Eq. 5
// (docs/notes/fit.md sections 4b and 5).
#include "dermis/offline/fit/surface_projection.h"

#include <algorithm>
#include <cmath>
#include <glm/mat3x3.hpp>
#include <limits>
#include <vector>

#include "dermis/surface/blend.h"
#include "dermis/surface/chart.h"
#include "dermis/surface/surface_evaluator.h"

namespace dermis {

int CornerOfVertex(const ManifoldDomain& domain, Index face, Index v) {
  for (int a = 0; a < 4; ++a) {
    if (domain.topology().face_vertex(face, a) == v) return a;
  }
  return -1;
}

bool InsideChart(const ManifoldDomain& domain, Index v, Vec2 z) {
  Index face = kInvalidIndex;
  Vec2 uv;
  if (!domain.ChartToFace(v, z, &face, &uv)) return false;
  const int c = CornerOfVertex(domain, face, v);
  if (c < 0) return false;
  const Vec2 cd = FaceToCorner(c, uv);
  const double ub = 1.0 - domain.options().blend_lb;
  return cd.x < ub && cd.y < ub;
}

bool EvaluateDomainJet(const ManifoldDomain& domain, const LocalPatch* patches, Index v, Vec2 z,
                       DomainJet* out) {
  Index face = kInvalidIndex;
  Vec2 uv;
  if (!domain.ChartToFace(v, z, &face, &uv)) return false;
  const int c = CornerOfVertex(domain, face, v);
  if (c < 0) return false;
  const MeshTopology& topo = domain.topology();
  const double lb = domain.options().blend_lb;
  const double ub = 1.0 - lb;
  DomainJet r;
  r.face = face;
  r.uv = uv;
  const Vec2 cd_v = FaceToCorner(c, uv);
  if (cd_v.x <= lb && cd_v.y <= lb) {
    // One chart: psi_v = 1, every other weight and gradient vanish.
    PatchFrame f;
    EvaluatePatchFrame(patches[v], z, &f);
    r.q = f.p, r.qx = f.px, r.qy = f.py;
    r.n = f.n, r.nx = f.nx, r.ny = f.ny;
    *out = r;
    return true;
  }
  Vec3 qu(0.0), qv(0.0), nu(0.0), nv(0.0);
  glm::dmat2 m_v(1.0);
  const Index base = topo.face_offset(face);
  double weights[4];
  Vec2 weight_gradients[4];
  FaceCornerWeights(domain.options().blend_type, lb, uv, weights, weight_gradients);
  for (int a = 0; a < 4; ++a) {
    const Vec2 cd = FaceToCorner(a, uv);
    const Index h = base + a;
    const Index va = topo.halfedge_origin(h);
    glm::dmat2 jac(1.0);
    Vec2 za;
    ChartMap(domain.chart(va), topo.halfedge_ring_index(h), cd, &za, &jac);
    const glm::dmat2 d = FaceToCornerJacobian(a);
    const glm::dmat2 m = jac * d;  // columns dz_a/du, dz_a/dv
    if (a == c) m_v = m;
    if (cd.x >= ub || cd.y >= ub) continue;
    const Vec2 grad = weight_gradients[a];
    const double psi = weights[a];
    const double psi_u = glm::dot(grad, d[0]);
    const double psi_v = glm::dot(grad, d[1]);
    PatchFrame f;
    EvaluatePatchFrame(patches[va], za, &f);
    const Vec3 pu = f.px * m[0].x + f.py * m[0].y;
    const Vec3 pv = f.px * m[1].x + f.py * m[1].y;
    const Vec3 fu = f.nx * m[0].x + f.ny * m[0].y;
    const Vec3 fv = f.nx * m[1].x + f.ny * m[1].y;
    r.q += psi * f.p;
    qu += psi_u * f.p + psi * pu;
    qv += psi_v * f.p + psi * pv;
    r.n += psi * f.n;
    nu += psi_u * f.n + psi * fu;
    nv += psi_v * f.n + psi * fv;
  }
  // d/dz_v = d/d(u, v) * (dz_v / d(u, v))^{-1}; m_v is regular off the vertex itself.
  const glm::dmat2 inv = glm::inverse(m_v);
  r.qx = qu * inv[0].x + qv * inv[0].y;
  r.qy = qu * inv[1].x + qv * inv[1].y;
  r.nx = nu * inv[0].x + nv * inv[0].y;
  r.ny = nu * inv[1].x + nv * inv[1].y;
  *out = r;
  return true;
}

Vec2 ProjectOntoPatch(const LocalPatch& patch, const Vec3& p, Vec2 z0, int max_iterations) {
  Vec2 z = z0;
  PatchJet j;
  EvaluatePatch(patch, z, &j);
  Vec3 r = j.p - p;
  double energy = glm::dot(r, r);
  for (int it = 0; it < max_iterations; ++it) {
    const double gx = glm::dot(j.px, r), gy = glm::dot(j.py, r);
    const double axx = glm::dot(j.px, j.px), axy = glm::dot(j.px, j.py), ayy = glm::dot(j.py, j.py);
    double hxx = axx + glm::dot(r, j.pxx), hxy = axy + glm::dot(r, j.pxy),
           hyy = ayy + glm::dot(r, j.pyy);
    double det = hxx * hyy - hxy * hxy;
    if (!(hxx > 0.0 && det > 1e-14 * axx * ayy)) {  // not positive definite: Gauss-Newton
      hxx = axx, hxy = axy, hyy = ayy;
      det = hxx * hyy - hxy * hxy;
      if (!(det > 1e-20 * axx * ayy) || !(det > 0.0)) break;
    }
    const Vec2 step(-(hyy * gx - hxy * gy) / det, -(hxx * gy - hxy * gx) / det);
    // Piegl-Tiller style stop: the residual is orthogonal to both tangents.
    const double rr = std::sqrt(energy);
    if (rr == 0.0 || (std::abs(gx) <= 1e-12 * rr * std::sqrt(axx) &&
                      std::abs(gy) <= 1e-12 * rr * std::sqrt(ayy))) {
      break;
    }
    double alpha = 1.0;
    bool accepted = false;
    for (int ls = 0; ls < 12; ++ls, alpha *= 0.5) {
      const Vec2 zn = z + alpha * step;
      PatchJet jn;
      EvaluatePatch(patch, zn, &jn);
      const Vec3 rn = jn.p - p;
      const double en = glm::dot(rn, rn);
      if (en <= energy) {
        z = zn, j = jn, r = rn, energy = en;
        accepted = true;
        break;
      }
    }
    if (!accepted || glm::dot(alpha * step, alpha * step) < 1e-30) break;
  }
  return z;
}

namespace {

double Norm(const Vec3& v) { return std::sqrt(glm::dot(v, v)); }

// Re-expresses a jet's point in the chart of its face's dominant corner.
void Rechart(const ManifoldDomain& domain, const DomainJet& jet, Index* v, Vec2* z) {
  const Vec2 uv = jet.uv;
  const int a = DominantCorner(uv);
  *v = domain.topology().face_vertex(jet.face, a);
  *z = domain.FaceToChart(jet.face, a, uv);
}

}  // namespace

CommonDisplacementSolution SolveCommonDisplacement(const ManifoldDomain& domain,
                                                   const LocalPatch* patches, const Vec3& p,
                                                   Index v0, Vec2 z0, double delta0,
                                                   double tolerance, int max_iterations) {
  CommonDisplacementSolution out;
  Index v = v0;
  Vec2 z = z0;
  double delta = delta0;
  DomainJet jet;
  if (!EvaluateDomainJet(domain, patches, v, z, &jet)) return out;
  Rechart(domain, jet, &v, &z);
  if (!EvaluateDomainJet(domain, patches, v, z, &jet)) return out;
  Vec3 f = jet.q + delta * jet.n - p;
  double norm = Norm(f);
  int it = 0;
  for (; it < max_iterations && norm > tolerance; ++it) {
    const glm::dmat3 j(jet.qx + delta * jet.nx, jet.qy + delta * jet.ny, jet.n);
    const double det = glm::determinant(j);
    if (!(std::abs(det) > 1e-300) || !std::isfinite(det)) break;
    const Vec3 step = -(glm::inverse(j) * f);
    if (!std::isfinite(step.x + step.y + step.z)) break;
    double alpha = 1.0;
    bool accepted = false;
    for (int ls = 0; ls < 12; ++ls, alpha *= 0.5) {
      const Vec2 zn = z + alpha * Vec2(step.x, step.y);
      const double dn = delta + alpha * step.z;
      DomainJet jn;
      if (!EvaluateDomainJet(domain, patches, v, zn, &jn)) continue;
      const Vec3 fn = jn.q + dn * jn.n - p;
      const double nn = Norm(fn);
      if (nn < norm) {
        z = zn, jet = jn, delta = dn, f = fn, norm = nn;
        accepted = true;
        break;
      }
    }
    if (!accepted) break;
    // Move to the chart of the dominant corner; the point itself does not change.
    Index vn = v;
    Vec2 zn = z;
    Rechart(domain, jet, &vn, &zn);
    DomainJet jr;
    if (vn != v && EvaluateDomainJet(domain, patches, vn, zn, &jr)) {
      v = vn, z = zn, jet = jr;
      f = jet.q + delta * jet.n - p;
      norm = Norm(f);
    }
  }
  out.converged = norm <= tolerance;
  out.face = jet.face;
  out.uv = jet.uv;
  out.delta = delta;
  out.residual = norm;
  out.iterations = it;
  return out;
}

}  // namespace dermis

namespace dermis {

namespace {

// The boundary edge of `face` nearest to uv if uv lies within `reach` of it (face coordinates),
// or -1. Gauss-Newton halves a step that would leave the surface, so it approaches a boundary
// edge without landing on it.
int BoundaryEdgeNear(const MeshTopology& topo, Index face, Vec2 uv, double reach) {
  const double d[4] = {uv.y, 1.0 - uv.x, 1.0 - uv.y, uv.x};
  int best = -1;
  for (int e = 0; e < 4; ++e) {
    if (d[e] <= reach && topo.twin(topo.face_offset(face) + e) == kInvalidIndex &&
        (best < 0 || d[e] < d[best])) {
      best = e;
    }
  }
  return best;
}

}  // namespace

// Half-edge h = face offset + e runs from corner e of its face to corner e + 1: face point
// CornerToFace(e, (t, 0)).
double ClosestPointOnBoundaryEdge(const ManifoldDomain& domain, const LocalPatch* patches,
                                  const Displacement* displacement, const Vec3& p, Index h,
                                  double lo, double hi, double* t) {
  const MeshTopology& topo = domain.topology();
  const Index f = topo.halfedge_face(h);
  const int e = static_cast<int>(h - topo.face_offset(f));
  auto distance = [&](double s) {
    SurfacePoint sp;
    if (!EvaluateSurface(domain, patches, displacement, f, CornerToFace(e, Vec2(s, 0.0)), &sp)) {
      return std::numeric_limits<double>::infinity();
    }
    return glm::length(sp.position - p);
  };
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double f1 = distance(x1), f2 = distance(x2);
  for (int it = 0; it < 30; ++it) {
    if (f1 < f2) {
      hi = x2, x2 = x1, f2 = f1, x1 = hi - g * (hi - lo), f1 = distance(x1);
    } else {
      lo = x1, x1 = x2, f1 = f2, x2 = lo + g * (hi - lo), f2 = distance(x2);
    }
  }
  *t = f2 < f1 ? x2 : x1;
  return std::min(f1, f2);
}

void ClosestPointAlongBoundary(const ManifoldDomain& domain, const LocalPatch* patches,
                               const Displacement* displacement, const Vec3& p,
                               const std::vector<Index>& faces, Index* face, Vec2* uv,
                               double* best) {
  const MeshTopology& topo = domain.topology();
  if (BoundaryEdgeNear(topo, *face, *uv, 0.05) < 0) return;
  auto distance = [&](Index f, int e, double t) {
    SurfacePoint sp;
    if (!EvaluateSurface(domain, patches, displacement, f, CornerToFace(e, Vec2(t, 0.0)), &sp)) {
      return std::numeric_limits<double>::infinity();
    }
    return glm::length(sp.position - p);
  };
  for (Index f : faces) {
    for (int e = 0; e < 4; ++e) {
      const Index h = topo.face_offset(f) + e;
      if (topo.twin(h) != kInvalidIndex) continue;
      constexpr int kSamples = 8;
      double bt = 0.0, bd = std::numeric_limits<double>::infinity();
      for (int i = 0; i <= kSamples; ++i) {
        const double t = static_cast<double>(i) / kSamples;
        const double dist = distance(f, e, t);
        if (dist < bd) bd = dist, bt = t;
      }
      double t = bt;
      const double d = ClosestPointOnBoundaryEdge(domain, patches, displacement, p, h,
                                                  std::max(0.0, bt - 1.0 / kSamples),
                                                  std::min(1.0, bt + 1.0 / kSamples), &t);
      if (d < bd) bd = d, bt = t;
      if (bd < *best) *best = bd, *face = f, *uv = CornerToFace(e, Vec2(bt, 0.0));
    }
  }
}

double ClosestPointOnSurface(const ManifoldDomain& domain, const LocalPatch* patches,
                             const Displacement* displacement, const Vec3& p, Index* face, Vec2* uv,
                             int max_iterations) {
  SurfacePoint s;
  if (!EvaluateSurface(domain, patches, displacement, *face, *uv, &s)) {
    return std::numeric_limits<double>::infinity();
  }
  Vec3 r = p - s.position;
  double energy = glm::dot(r, r);
  for (int it = 0; it < max_iterations && energy > 0.0; ++it) {
    // Gauss-Newton step in the dominant corner's chart: (J^T J) dz = J^T r.
    const double axx = glm::dot(s.dx, s.dx), axy = glm::dot(s.dx, s.dy), ayy = glm::dot(s.dy, s.dy);
    const double gx = glm::dot(s.dx, r), gy = glm::dot(s.dy, r);
    const double det = axx * ayy - axy * axy;
    if (!(det > 1e-24 * axx * ayy) || !std::isfinite(det)) break;
    const Vec2 step((ayy * gx - axy * gy) / det, (axx * gy - axy * gx) / det);
    const Vec2 z = domain.FaceToChart(*face, s.chart_corner, *uv);
    bool accepted = false;
    double alpha = 1.0;
    for (int ls = 0; ls < 10; ++ls, alpha *= 0.5) {
      Index f2 = kInvalidIndex;
      Vec2 uv2;
      if (!domain.ChartToFace(s.chart_vertex, z + alpha * step, &f2, &uv2)) continue;
      SurfacePoint s2;
      if (!EvaluateSurface(domain, patches, displacement, f2, uv2, &s2)) continue;
      const Vec3 r2 = p - s2.position;
      const double e2 = glm::dot(r2, r2);
      if (e2 < energy) {
        *face = f2, *uv = uv2, s = s2, r = r2, energy = e2;
        accepted = true;
        break;
      }
    }
    if (!accepted || alpha * alpha * glm::dot(step, step) < 1e-28 * (axx + ayy)) break;
  }
  double distance = std::sqrt(energy);
  // Beside a boundary edge the steps above stop short of a closest point on the boundary (each
  // one that leaves the surface is halved, its part along the boundary with it): search along
  // the boundary edges of the faces around this one.
  if (BoundaryEdgeNear(domain.topology(), *face, *uv, 0.05) >= 0) {
    const MeshTopology& topo = domain.topology();
    std::vector<Index> faces;
    for (int a = 0; a < 4; ++a) {
      const Index v = topo.face_vertex(*face, a);
      for (int i = 0; i < topo.valence(v); ++i) faces.push_back(topo.ring(v, i).face);
    }
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    ClosestPointAlongBoundary(domain, patches, displacement, p, faces, face, uv, &distance);
  }
  return distance;
}

}  // namespace dermis

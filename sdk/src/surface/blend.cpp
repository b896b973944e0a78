// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Partition-of-unity steps of Ying-Zorin (docs/notes/manifold.md section 4): the C-infinity
// "analytic" step (S1 pou1d / S2 blendFunc1D) and the C2 cubic B-spline step 1 - C(3t).
#include "dermis/surface/blend.h"

#include <cmath>

namespace dermis {
namespace {

// A(t) = 2 e^{-1/t} / (t - 1) and A(1 - t) = -2 e^{-1/(1-t)} / t on (0, 1), with their
// derivatives d/dt. Both are written so that neither divides by a rounded 1 - t: for t below
// 1e-3 (or 1 - t below 1e-3) e^{-1/t} < 1e-434 underflows to zero in double precision, so the
// terms are exactly 0 there.
void AnalyticA(double t, double* a, double* da, double* a_comp, double* da_comp) {
  const double s = 1.0 - t;
  *a = *da = *a_comp = *da_comp = 0.0;
  if (t >= 1e-3) {
    const double e = std::exp(-1.0 / t);
    *a = 2.0 * e / (t - 1.0);
    *da = 2.0 * e * ((t - 1.0) / (t * t) - 1.0) / ((t - 1.0) * (t - 1.0));
  }
  if (s >= 1e-3) {
    const double e = std::exp(-1.0 / s);
    *a_comp = -2.0 * e / t;
    *da_comp = 2.0 * e * (t / (s * s) + 1.0) / (t * t);
  }
}

// Cubic B-spline cumulative C(x) on [0, 3] and C'(x).
void CubicC(double x, double* c, double* dc) {
  if (x <= 1.0) {
    *c = x * x * x / 6.0;
    *dc = 0.5 * x * x;
  } else if (x <= 2.0) {
    *c =
        1.0 / 6.0 + (3.0 * (x * x - 1.0) - 3.0 * (x - 1.0) - (2.0 / 3.0) * (x * x * x - 1.0)) / 2.0;
    *dc = 3.0 * x - 1.5 - x * x;
  } else {
    const double y = 3.0 - x;
    *c = 1.0 - y * y * y / 6.0;
    *dc = 0.5 * y * y;
  }
}

}  // namespace

double BlendStep(BlendType type, double t, double* derivative) {
  if (derivative) *derivative = 0.0;
  if (!(t > 0.0)) return 1.0;  // also catches NaN as "outside"
  if (t >= 1.0) return 0.0;
  if (type == BlendType::kC2) {
    double c, dc;
    CubicC(3.0 * t, &c, &dc);
    if (derivative) *derivative = -3.0 * dc;
    return 1.0 - c;
  }
  // beta = e^{A(t)} / (e^{A(t)} + e^{A(1-t)}) = 1 / (1 + e^{g}), g = A(1-t) - A(t).
  double a0, da0, a1, da1;
  AnalyticA(t, &a0, &da0, &a1, &da1);
  const double g = a1 - a0;
  const double beta = 1.0 / (1.0 + std::exp(g));
  if (derivative && beta > 0.0 && beta < 1.0) {
    *derivative = -beta * (1.0 - beta) * (da1 - da0);
  }
  return beta;
}

double CornerWeight(BlendType type, double lb, Vec2 cd, Vec2* gradient) {
  const double inv = 1.0 / (1.0 - 2.0 * lb);  // 1 / (ub - lb)
  double dbc, dbd;
  const double bc = BlendStep(type, (cd.x - lb) * inv, &dbc);
  const double bd = BlendStep(type, (cd.y - lb) * inv, &dbd);
  if (gradient) *gradient = Vec2(dbc * inv * bd, bc * dbd * inv);
  return bc * bd;
}

void FaceCornerWeights(BlendType type, double lb, Vec2 uv, double psi[4], Vec2 gradient[4]) {
  const double inv = 1.0 / (1.0 - 2.0 * lb);
  // The steps at the corner coordinates FaceToCorner() gives: u, 1 - u, v, 1 - v.
  const double x[4] = {uv.x, 1.0 - uv.x, uv.y, 1.0 - uv.y};
  double b[4], db[4];
  for (int k = 0; k < 4; ++k) b[k] = BlendStep(type, (x[k] - lb) * inv, &db[k]);
  // Corner a's (c, d): 0 (u, v), 1 (v, 1 - u), 2 (1 - u, 1 - v), 3 (1 - v, u).
  const int c[4] = {0, 2, 1, 3}, d[4] = {2, 1, 3, 0};
  for (int a = 0; a < 4; ++a) {
    const double bc = b[c[a]], bd = b[d[a]];
    if (gradient) gradient[a] = Vec2(db[c[a]] * inv * bd, bc * db[d[a]] * inv);
    psi[a] = bc * bd;
  }
}

}  // namespace dermis

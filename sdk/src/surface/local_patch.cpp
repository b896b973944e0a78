// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Bi-quadratic local patch of Yoon, Eq. 1: P(x,y) = [x^2 x 1] C [y^2 y 1]^T.
#include "dermis/surface/local_patch.h"

#include <cmath>

namespace dermis {

void EvaluatePatch(const LocalPatch& patch, Vec2 z, PatchJet* out) {
  const double x = z.x, y = z.y;
  const double xm[3] = {1.0, x, x * x};
  const double ym[3] = {1.0, y, y * y};
  const double dxm[3] = {0.0, 1.0, 2.0 * x};
  const double dym[3] = {0.0, 1.0, 2.0 * y};
  const double ddm[3] = {0.0, 0.0, 2.0};
  Vec3 p(0.0), px(0.0), py(0.0), pxx(0.0), pxy(0.0), pyy(0.0);
  for (int m = 0; m < 3; ++m) {
    for (int n = 0; n < 3; ++n) {
      const Vec3& c = patch.coeff[m][n];
      p += (xm[m] * ym[n]) * c;
      px += (dxm[m] * ym[n]) * c;
      py += (xm[m] * dym[n]) * c;
      pxx += (ddm[m] * ym[n]) * c;
      pxy += (dxm[m] * dym[n]) * c;
      pyy += (xm[m] * ddm[n]) * c;
    }
  }
  *out = PatchJet{p, px, py, pxx, pxy, pyy};
}

void EvaluatePatchFrame(const LocalPatch& patch, Vec2 z, PatchFrame* out) {
  PatchJet j;
  EvaluatePatch(patch, z, &j);
  PatchFrame f{j.p, j.px, j.py, patch.fallback_normal, Vec3(0.0), Vec3(0.0)};
  const Vec3 n = glm::cross(j.px, j.py);
  const double len = std::sqrt(glm::dot(n, n));
  const double scale = std::sqrt(glm::dot(j.px, j.px) * glm::dot(j.py, j.py));
  if (len > 1e-14 * scale && std::isfinite(len)) {
    f.n = n / len;
    // d(n/|n|) = (dn - N (N . dn)) / |n|, dn from the patch's second derivatives.
    const Vec3 nx = glm::cross(j.pxx, j.py) + glm::cross(j.px, j.pxy);
    const Vec3 ny = glm::cross(j.pxy, j.py) + glm::cross(j.px, j.pyy);
    f.nx = (nx - f.n * glm::dot(f.n, nx)) / len;
    f.ny = (ny - f.n * glm::dot(f.n, ny)) / len;
  }
  *out = f;
}

}  // namespace dermis

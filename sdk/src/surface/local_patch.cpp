// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Bi-quadratic local patch of Yoon, Eq. 1: P(x,y) = [x^2 x 1] C [y^2 y 1]^T.
#include "dermis/surface/local_patch.h"

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

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Test support: a smooth displacement per chart (header only; the surface module).
#pragma once

#include <cmath>

#include "dermis/surface/displacement.h"

namespace dermis::test {

/// d_v(x, y) = amplitude * sin(x + 0.3 v) * cos(1.3 y - 0.1 v): a different smooth function per
/// chart, to exercise the blending of displaced patches.
class WavyDisplacement final : public Displacement {
 public:
  explicit WavyDisplacement(double amplitude) : amplitude_(amplitude) {}
  void Evaluate(Index v, Vec2 z, double* value, Vec2* gradient) const override {
    const double a = z.x + 0.3 * v, b = 1.3 * z.y - 0.1 * v;
    *value = amplitude_ * std::sin(a) * std::cos(b);
    *gradient =
        Vec2(amplitude_ * std::cos(a) * std::cos(b), -1.3 * amplitude_ * std::sin(a) * std::sin(b));
  }

 private:
  double amplitude_;
};

}  // namespace dermis::test

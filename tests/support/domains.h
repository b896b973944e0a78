// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Test support: manifold domains built from polygon meshes (the build stage makes them, as only
// it can), and a smooth displacement per chart. Links dermis::offline_build.
#pragma once

#include <cmath>

#include "dermis/offline/build/domain_builder.h"
#include "dermis/surface/displacement.h"
#include "support/meshes.h"

namespace dermis::test {

/// Builds the control surface, failing the test on error.
ControlSurface Build(const PolygonMesh& mesh, const DomainOptions& options = DomainOptions{});

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

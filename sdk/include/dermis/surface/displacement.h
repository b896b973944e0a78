// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Scalar displacement functions per chart (paper Eq. 3).
#pragma once

#include "dermis/core/types.h"

namespace dermis {

/// A scalar function d_v(x, y) on the chart of every control vertex v. The displaced patch is
/// S_v = P_v + d_v N_v (paper Eq. 3), N_v the unit normal of the local patch P_v.
/// Implementations must be thread-safe for concurrent Evaluate() calls and must not allocate.
class Displacement {
 public:
  virtual ~Displacement() = default;
  /// Value and gradient d/d(x, y) of the displacement of vertex `vertex`'s chart at chart point
  /// z. Units: model units (the same as the control mesh positions).
  virtual void Evaluate(Index vertex, Vec2 z, double* value, Vec2* gradient) const = 0;
};

/// d = 0 everywhere: the displaced surface is the domain surface.
class ZeroDisplacement final : public Displacement {
 public:
  void Evaluate(Index, Vec2, double* value, Vec2* gradient) const override {
    *value = 0.0;
    *gradient = Vec2(0.0);
  }
};

}  // namespace dermis

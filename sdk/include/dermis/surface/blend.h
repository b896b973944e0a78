// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Partition of unity of the Ying-Zorin manifold (docs/notes/manifold.md section 4).
///
/// A chart's weight in a face is a product of two 1-D steps in its corner coordinates (c, d):
/// psi = beta(tau(c)) * beta(tau(d)), tau(x) = (x - lb) / (ub - lb), lb + ub = 1. Because
/// beta(t) + beta(1 - t) = 1 the four corner weights of a face sum to one exactly, so no
/// normalisation is needed. psi is 1 on [0, lb]^2 (the "one chart" region) and 0 once c or d
/// reaches ub.
#pragma once

#include "dermis/core/types.h"

namespace dermis {

/// Which 1-D step the partition of unity uses.
enum class BlendType : std::uint8_t {
  kCInfinity = 0,  ///< beta = e^A(t) / (e^A(t) + e^A(1-t)), A(t) = 2 e^(-1/t) / (t - 1). Default.
  kC2 = 1,         ///< Cubic B-spline step 1 - C(3t) (Ying-Zorin's `pouctrl=1`).
};

/// The 1-D step: 1 for t <= 0, 0 for t >= 1, smooth in between, beta(t) + beta(1-t) = 1.
/// If `derivative` is not null it receives d beta / dt.
double BlendStep(BlendType type, double t, double* derivative = nullptr);

/// Weight of a corner chart at corner coordinates cd = (c, d) in [0,1]^2 with blending window
/// [lb, 1 - lb] (0 < lb < 1/2). If `gradient` is not null it receives d psi / d(c, d).
double CornerWeight(BlendType type, double lb, Vec2 cd, Vec2* gradient = nullptr);

/// The four corner weights of face point uv: psi[a] = CornerWeight(type, lb, FaceToCorner(a,
/// uv)), bit for bit, and with `gradient` not null gradient[a] as CornerWeight gives it (d psi /
/// d(c, d) of corner a). The corners' coordinates are u, 1 - u, v and 1 - v in turn, so the
/// four steps are evaluated once each instead of twice.
void FaceCornerWeights(BlendType type, double lb, Vec2 uv, double psi[4],
                       Vec2 gradient[4] = nullptr);

}  // namespace dermis

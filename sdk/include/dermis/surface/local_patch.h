// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Yoon's bi-quadratic local patch (paper Eq. 1) and its derivatives.
#pragma once

#include "dermis/core/types.h"

namespace dermis {

/// P(x, y) = sum_{m,n=0..2} coeff[m][n] x^m y^n over chart coordinates (x, y) (paper Eq. 1).
/// coeff[0][0] is the chart's vertex, so P(0, 0) interpolates it.
struct LocalPatch {
  Vec3 coeff[3][3] = {};
  /// Unit normal used where the patch itself is degenerate (cross product of its first
  /// derivatives vanishes): the area-weighted normal of the control vertex's one-ring.
  Vec3 fallback_normal{0.0, 0.0, 1.0};
};

/// Value and derivatives up to second order of a local patch at one chart point.
struct PatchJet {
  Vec3 p, px, py, pxx, pxy, pyy;
};

/// Evaluates the patch and its first and second derivatives at chart point z.
void EvaluatePatch(const LocalPatch& patch, Vec2 z, PatchJet* out);

/// A local patch, its unit normal and their first derivatives at one chart point: the moving
/// frame along which a displacement is applied (paper Eq. 3).
struct PatchFrame {
  Vec3 p, px, py;  ///< Position and d/dx, d/dy.
  /// Unit normal (px x py)/|px x py| and its derivatives; the patch's fallback_normal and zero
  /// derivatives where the patch is degenerate.
  Vec3 n, nx, ny;
};

/// Evaluates the patch's frame at chart point z.
void EvaluatePatchFrame(const LocalPatch& patch, Vec2 z, PatchFrame* out);

/// The 8 free monomials x^m y^n of the patch, in the row order used by patch-fit operators:
/// (1,0) (0,1) (2,0) (1,1) (0,2) (2,1) (1,2) (2,2).
constexpr int kPatchMonomials[8][2] = {{1, 0}, {0, 1}, {2, 0}, {1, 1},
                                       {0, 2}, {2, 1}, {1, 2}, {2, 2}};

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Fits the control-vertex positions so that the blended domain surface (paper Eq. 1-2
/// and 4 without displacement) passes close to the data: linear least squares at fixed surface
/// parameters (docs/fitting.md, "Control-vertex fit").
///
/// Simplification leaves the control vertices on the data, and the smooth domain surface then
/// cuts every sharp or thin feature (an ear tip, the rim of a base) by up to several percent of
/// the model: the displacement there is large, changes fast and may not be a height field. The
/// domain surface Q(z) = sum_a psi_a P_a(theta_a(z)) is linear in the control positions X for a
/// fixed parameter z, because each patch P_a is the fit operator applied to X (Eq. 2). So
/// min_X sum_i |Q(z_i; X) - p_i|^2 is a sparse linear least-squares problem; alternated with
/// reprojection it is the classic parameter-correction scheme (Hoppe et al. 1994; Marinov and
/// Kobbelt 2004). By default each residual is measured mostly across the surface
/// (ControlFitOptions::tangent_weight, tangent-distance minimisation), which converges much
/// faster because the surface may slide along itself between reprojections.
#pragma once

#include <utility>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/offline/fit/point_fit.h"
#include "dermis/surface/manifold_domain.h"

namespace dermis {

/// The domain surface at (face, uv) as a linear combination of control positions:
/// Q(face, uv) = sum_k weight_k X[vertex_k]. Pairs (vertex, weight) are appended to *out, a
/// vertex may appear more than once. Returns false (appending nothing) for an invalid face or
/// uv outside [0,1]^2.
bool DomainSurfaceStencil(const ManifoldDomain& domain, Index face, Vec2 uv,
                          std::vector<std::pair<Index, double>>* out);

/// Options of FitControlPositions().
struct ControlFitOptions {
  /// Damping: each vertex is also pulled towards its current position with this fraction of
  /// its own data weight (the diagonal of the normal equations), which keeps the step where
  /// the reprojected parameters stay valid; at least a hundredth of the mean diagonal, so a
  /// vertex with little or no data stays (nearly) where it is.
  double damping = 0.05;
  /// Residuals above this multiple of the median residual (at least 1e-9 of the data's size)
  /// get a weight that decays as (cutoff / r)^2 (a Cauchy-like robust loss against
  /// misprojected points); <= 0 turns the robust weights off.
  double robust_cutoff = 8.0;
  /// Weight of a residual's part along the domain surface against its part across it: each
  /// point costs r^T (t I + (1 - t) n n^T) r, r = Q(z) - p, n the surface normal at z. 1 is
  /// the point distance |r|^2, which holds every point to its parameter and converges slowly;
  /// below 1 the surface may slide along itself and the next round's projection follows
  /// (tangent-distance minimisation; Wang, Pottmann and Liu 2006). In faces with a boundary
  /// vertex the point distance is kept, so the surface's boundary stays at the data's.
  /// docs/fitting.md, "Control-vertex fit" has the measurements behind the default.
  double tangent_weight = 0.01;
  /// Damping along the surface: a vertex's move across its one-ring normal is pulled back with
  /// at least this fraction of its data weight (the larger of this and `damping`), so the
  /// sliding the tangent weight allows does not skew the control quads. <= damping: none.
  /// A vertex's data weight is the mean of its three diagonal entries in the normal
  /// equations: (1 + 2 t) / 3 of the point distance's (t the tangent weight), so with t = 0.01
  /// both dampings act on about a third of the weight they act on with t = 1.
  double tangent_damping = 0.3;
  /// Weight of the corner patches' agreement (unitless, >= 0): each point also costs
  /// patch_agreement * sum_a psi_a |P_a(z_a) - Q(z)|^2, over the corner patches blended at its
  /// parameter, so the patches are held to one surface and not only their blend. It makes the
  /// per-chart projections consistent (the paper's error without optimisation) at the cost of
  /// the blend's distance to the data; docs/fitting.md, "Control-vertex fit" and
  /// "Noise-adaptive control fit" have the measurements (0: off; FitOptions::control_fit sets
  /// 1, which FitSurface scales down on clean data with tangent_damping).
  double patch_agreement = 0.0;
  int threads = 0;  ///< 0: hardware concurrency. Results do not depend on it.
};

/// One least-squares step: new control positions minimising sum_i |Q(z_i; X) - p_i|^2 (with
/// damping, robust weights, the tangent weight and, if set, the patch-agreement term) at the
/// parameters of `fits` (points with kOutside status are ignored). `positions` holds the current
/// positions on entry and the fitted ones on return. Deterministic whatever the thread count. Fails
/// (leaving positions unchanged) if the system cannot be solved.
Status FitControlPositions(const ManifoldDomain& domain, const std::vector<Vec3>& points,
                           const std::vector<PointFit>& fits, const ControlFitOptions& options,
                           std::vector<Vec3>* positions);

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Penalised least squares for one uniform cubic B-spline lattice: the smoothing spline
/// that replaces the plain BA step at each chart's finest level (docs/fitting.md, "Finest
/// level: a smoothing spline"; docs/notes/fit.md section 4c).
#pragma once

#include <cstddef>
#include <vector>

#include "dermis/core/types.h"

namespace dermis {

/// Minimises, over the (m + 3)^2 coefficients phi of a lattice with m cells per side on
/// [-half_extent, half_extent]^2,
///
///   sum_c (f_phi(z_c) - r_c)^2 + lambda (E(phi) + tension G(phi) + 1e-6 |phi - phi_0|^2),
///   E(phi) = sum (phi_xx^2 + 2 phi_xy^2 + phi_yy^2)   (second differences of the coefficients),
///   G(phi) = sum g (phi_x^2 + phi_y^2)                (first differences, weighted by g),
///   lambda = smoothing * count / (m + 3)^2,
///
/// so `smoothing` weighs the discrete thin-plate energy per lattice node against the squared
/// residual per point, whatever the lattice size. Among the functions that fit the residuals
/// about equally well it picks the one that bends least, which is what keeps a tessellation of
/// the surface close to it between the data points (BA leaves a bump at each point instead).
/// g is 1 in gaps of the data and falls to 0 where the data is dense (g = 0.1 w / (0.1 w + w_k)
/// with w_k the node's data weight and w its mean): the membrane term keeps the spline from
/// continuing a steep slope across a gap, where a thin plate alone swings far past the data
/// (seen as spikes at the tips of the bunny's ears). phi_0 is the start.
/// Only the nodes within one node of some point's 4 x 4 support are unknowns; the others are
/// set to 0 (as BA leaves them), so the spline never extrapolates into a part of the chart
/// without data.
/// Solved by conjugate gradients with a Jacobi preconditioner, matrix-free, starting from *phi
/// (in: a start, for example the BA solution; out: the solution), for at most `iterations`
/// steps or until the residual norm falls below 1e-8 of the right-hand side's. Deterministic.
/// Points outside the square are clamped onto it.
/// \param phi  (m + 3)^2 coefficients, row-major in y then x (BsplineDisplacementData layout).
void SmoothBsplineFit(const Vec2* z, const double* r, std::size_t count, double half_extent, int m,
                      double smoothing, double tension, int iterations, std::vector<double>* phi);

}  // namespace dermis

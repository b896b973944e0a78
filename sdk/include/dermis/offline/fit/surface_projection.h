// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Point projection onto local patches and onto the blended domain surface
/// (paper section 4, "Initial displacements" and Eq. 5; docs/notes/fit.md sections 4b and 5).
#pragma once

#include <vector>

#include "dermis/core/types.h"
#include "dermis/surface/local_patch.h"
#include "dermis/surface/manifold_domain.h"

namespace dermis {

/// The blended domain surface Q = sum_a psi_a P_a (Eq. 4 without displacement) and the blended
/// patch normal N~ = sum_a psi_a N_a (not unit length), with their derivatives in the chart of
/// one vertex, at one point.
struct DomainJet {
  Vec3 q{0.0}, qx{0.0}, qy{0.0};
  Vec3 n{0.0}, nx{0.0}, ny{0.0};
  Index face = kInvalidIndex;  ///< The face that holds the point.
  Vec2 uv{0.0};                ///< Its face coordinates.
};

/// Evaluates the jet at chart point z of vertex v. Returns false if z lies outside v's star.
bool EvaluateDomainJet(const ManifoldDomain& domain, const LocalPatch* patches, Index v, Vec2 z,
                       DomainJet* out);

/// Index (0..3) of vertex v among the corners of `face`, or -1.
int CornerOfVertex(const ManifoldDomain& domain, Index face, Index v);

/// Whether chart v has a positive blending weight at chart point z (z lies in U_v).
bool InsideChart(const ManifoldDomain& domain, Index v, Vec2 z);

/// Closest point of one bi-quadratic patch to p by Newton's method on |P(z) - p|^2 / 2 from z0
/// (docs/notes/fit.md section 5): Gauss-Newton where the Hessian is not positive definite,
/// backtracking, at most `max_iterations` steps. Returns the parameter; the patch is a
/// polynomial, so the result may lie outside the chart (check with InsideChart()).
Vec2 ProjectOntoPatch(const LocalPatch& patch, const Vec3& p, Vec2 z0, int max_iterations);

/// Result of solving Q(z) + delta N~(z) = p (docs/notes/fit.md section 4b).
struct CommonDisplacementSolution {
  bool converged = false;
  Index face = kInvalidIndex;
  Vec2 uv{0.0};
  double delta = 0.0;
  double residual = 0.0;  ///< |Q + delta N~ - p| at the returned point (model units).
  int iterations = 0;
};

/// Newton's method on the square 3x3 system F(z, delta) = Q(z) + delta N~(z) - p = 0 from
/// chart point z0 of vertex v0 and displacement delta0, with backtracking. After every step the
/// point is re-expressed in the chart of its face's dominant corner, so it may move across faces
/// and stays in a regular parametrisation at extraordinary vertices. `tolerance` is the
/// residual (model units) at which it stops.
CommonDisplacementSolution SolveCommonDisplacement(const ManifoldDomain& domain,
                                                   const LocalPatch* patches, const Vec3& p,
                                                   Index v0, Vec2 z0, double delta0,
                                                   double tolerance, int max_iterations = 30);

}  // namespace dermis

namespace dermis {

class Displacement;

/// Closest point of the displaced surface to p, by Gauss-Newton on |D(z) - p|^2 in the chart
/// of the dominant corner, starting at (face, uv) and moving across faces as needed. Gives a
/// local minimum: an upper bound on the true distance that is exact when the start is in the
/// right basin (the fitted parameter of a point is). Where it ends within 0.05 (face
/// coordinates) of a boundary edge, ClosestPointAlongBoundary() over the faces around the final
/// face follows: a step that would leave the surface is halved, so Gauss-Newton alone stops
/// short of a closest point on the boundary. Returns the distance (model units) and writes the
/// final parameter.
double ClosestPointOnSurface(const ManifoldDomain& domain, const LocalPatch* patches,
                             const Displacement* displacement, const Vec3& p, Index* face, Vec2* uv,
                             int max_iterations = 20);

/// The closest point to p of the displaced surface along boundary half-edge h (a half-edge with
/// no twin; the surface at parameter t in [0, 1] from its origin to its destination), searched
/// by golden sections on [lo, hi] (30 steps, 0 <= lo < hi <= 1; the distance must be unimodal
/// there). Writes t and returns the distance (model units; +inf where the surface cannot be
/// evaluated).
double ClosestPointOnBoundaryEdge(const ManifoldDomain& domain, const LocalPatch* patches,
                                  const Displacement* displacement, const Vec3& p, Index h,
                                  double lo, double hi, double* t);

/// If (face, uv) lies within 0.05 (face coordinates) of a boundary edge of its face: the closest
/// point to p along every boundary edge of `faces` (8 samples per edge, then golden sections
/// around the best) replaces (face, uv) and *distance (model units) where it is closer than
/// *distance. Nothing happens elsewhere.
void ClosestPointAlongBoundary(const ManifoldDomain& domain, const LocalPatch* patches,
                               const Displacement* displacement, const Vec3& p,
                               const std::vector<Index>& faces, Index* face, Vec2* uv,
                               double* distance);

}  // namespace dermis

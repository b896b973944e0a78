// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Evaluation of the blended domain surface and the displaced surface at (face, u, v)
/// (paper Eq. 3-4, docs/notes/manifold.md section 6).
#pragma once

#include <cstddef>

#include "dermis/surface/displacement.h"
#include "dermis/surface/local_patch.h"
#include "dermis/surface/manifold_domain.h"

namespace dermis {

/// A sample of the surface.
struct SurfacePoint {
  Vec3 position{0.0};
  /// Unit normal, never NaN: from the derivatives in the dominant corner chart, falling back to
  /// the one-ring normal of the control mesh where the surface is degenerate.
  Vec3 normal{0.0, 0.0, 1.0};
  /// dS/du, dS/dv in face coordinates. Not defined at an extraordinary vertex itself, where the
  /// face parametrisation is singular (|dS/du| ~ r^(p-1)); face_derivatives_valid says so and
  /// both are zero there.
  Vec3 du{0.0}, dv{0.0};
  bool face_derivatives_valid = false;
  /// dS/dx, dS/dy in the chart of the dominant corner (the corner whose quarter of the face
  /// holds the point): a regular parametrisation everywhere, also at extraordinary vertices.
  Vec3 dx{0.0}, dy{0.0};
  Index chart_vertex = kInvalidIndex;  ///< The dominant corner's vertex.
  int chart_corner = 0;                ///< Its corner index in the face.
};

/// Checks that `face` is a face of the domain and that uv lies in [0,1]^2 (within 1e-12, then
/// clamped onto it): the parameters EvaluateSurface() accepts.
bool ClampFaceCoordinates(const ManifoldDomain& domain, Index face, Vec2* uv);

/// Evaluates the surface at face coordinates uv in [0,1]^2 of `face`.
/// \param patches       ManifoldDomain::num_vertices() patches fitted by FitPatches().
/// \param displacement  the scalar displacement per chart, or null for the domain surface.
/// \return false (and leaves *out untouched) if the face is out of range or uv is outside
///         [0,1]^2 or not finite.
bool EvaluateSurface(const ManifoldDomain& domain, const LocalPatch* patches,
                     const Displacement* displacement, Index face, Vec2 uv, SurfacePoint* out);

/// Value and first derivatives d/d(x, y) of one displaced chart patch S_v = P_v + d_v N_v at
/// chart point z (paper Eq. 3). With a null displacement, S_v = P_v.
void EvaluateChartSurface(const LocalPatch& patch, const Displacement* displacement, Index vertex,
                          Vec2 z, Vec3* position, Vec3* dx, Vec3* dy);

}  // namespace dermis

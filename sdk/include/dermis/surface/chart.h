// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Ying-Zorin charts: corner maps, chart maps, their inverses and Jacobians
/// (docs/notes/manifold.md sections 0, 2, 3 and 7).
///
/// Face coordinates W = (s, t) in [0,1]^2 put corner 0 at (0,0), 1 at (1,0), 2 at (1,1), 3 at
/// (0,1). Corner a has local coordinates w = (c, d) with the corner at 0, the c-axis along the
/// edge to the next corner and the d-axis along the edge to the previous one. A vertex's chart
/// maps w of ring face f to z = e^{i f Theta / K} r^p e^{i q alpha}, where w = r e^{i alpha},
/// K is the number of faces around the vertex, Theta the angle of the chart's sector (2 pi
/// inside, pi on a boundary edge, pi/2 or 3pi/2 at a boundary corner) and q = 2 Theta / (pi K).
#pragma once

#include <glm/mat2x2.hpp>

#include "dermis/core/types.h"

namespace dermis {

/// How the radius of a chart is scaled (docs/notes/manifold.md section 2).
enum class ChartType : std::uint8_t {
  /// p = log2(1 / lambda_K), lambda_K the subdominant eigenvalue of Catmull-Clark subdivision
  /// at valence K (p = 1 on boundaries). Follows Catmull-Clark spacing. Default.
  kCharacteristicMap = 0,
  /// p = q: the holomorphic map z = w^q, rotated per face.
  kFullyComplex = 1,
  /// p = 1: radii are kept.
  kIsodistance = 2,
};

/// What kind of chart a vertex gets (docs/notes/manifold.md section 7).
enum class VertexKind : std::uint8_t {
  kInterior = 0,       ///< Full disk, sector 2 pi.
  kCrease = 1,         ///< Boundary vertex, half disk, sector pi.
  kConvexCorner = 2,   ///< Boundary corner, quarter disk, sector pi/2.
  kConcaveCorner = 3,  ///< Boundary corner, three-quarter disk, sector 3 pi/2.
};

/// Parameters of one vertex chart.
struct ChartParams {
  int valence = 4;  ///< Number of faces around the vertex (K).
  VertexKind kind = VertexKind::kInterior;
  double sector = 6.283185307179586;  ///< Theta: total angle of the chart's image.
  double p = 1.0;                     ///< Radial exponent.
  double q = 1.0;                     ///< Angular exponent, q = 2 Theta / (pi K).
};

/// lambda_K = [5 + cos(2pi/K) + cos(pi/K) sqrt(2 (9 + cos(2pi/K)))] / 16 (K >= 3).
double CatmullClarkSubdominantEigenvalue(int valence);

/// The sector angle Theta of a vertex kind.
double SectorAngle(VertexKind kind);

/// Chart parameters for a vertex of `valence` faces (>= 1; >= 3 for interior vertices).
ChartParams MakeChartParams(int valence, VertexKind kind, ChartType type);

/// A_a: corner coordinates (c, d) of corner a (0..3) to face coordinates (s, t).
Vec2 CornerToFace(int corner, Vec2 w);
/// A_a^{-1}: face coordinates (s, t) to the corner coordinates of corner a.
Vec2 FaceToCorner(int corner, Vec2 face_uv);
/// d(c, d) / d(s, t) of corner a: a rotation by -a * 90 degrees (columns: d/ds, d/dt).
glm::dmat2 FaceToCornerJacobian(int corner);
/// The corner whose quarter [0, 1/2]^2 of the face holds face point uv (ties go to the
/// lower quarter): the dominant chart of the point.
int DominantCorner(Vec2 face_uv);
/// T_delta: corner coordinates of corner a to those of corner (a + delta) mod 4 of the same face.
Vec2 CornerTransition(int delta, Vec2 w);

/// The chart map z = phi(f, w) of ring face f. If `jacobian` is not null it receives dz/d(c, d)
/// (columns dz/dc, dz/dd). Returns false when the Jacobian does not exist (w = 0 and p or q is
/// not 1: the chart map is not differentiable at its vertex); the value is still valid then.
bool ChartMap(const ChartParams& chart, int face_in_ring, Vec2 w, Vec2* z,
              glm::dmat2* jacobian = nullptr);

/// Inverse chart map: the ring face and corner coordinates of chart point z. Returns false when
/// z lies outside a boundary chart's sector. z = 0 gives face 0, w = 0.
bool ChartMapInverse(const ChartParams& chart, Vec2 z, int* face_in_ring, Vec2* w);

}  // namespace dermis

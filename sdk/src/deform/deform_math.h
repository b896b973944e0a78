// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Private to the deformers: small math shared by LBS, DQS and the sweep (finite checks, unit
// dual quaternions, swing-twist, normalised weights). Header-only, core + GLM.
#pragma once

#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include "dermis/deform/deformer.h"

namespace dermis::deform {

inline bool IsFinite(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

/// Weights scaled to sum 1 (the caller has validated a positive sum).
inline glm::dvec4 NormalizedWeights(const VertexWeights& w) {
  const glm::dvec4 d(w.weights);
  const double sum = d.x + d.y + d.z + d.w;
  return d / sum;
}

/// A unit dual quaternion: rotation `real`, translation t encoded as dual = 0.5 * t * real.
struct DualQuat {
  glm::dquat real{1.0, 0.0, 0.0, 0.0};
  glm::dquat dual{0.0, 0.0, 0.0, 0.0};
};

inline DualQuat MakeDualQuat(const glm::dquat& rotation, const glm::dvec3& translation) {
  DualQuat d;
  d.real = rotation;
  d.dual = 0.5 * (glm::dquat(0.0, translation.x, translation.y, translation.z) * rotation);
  return d;
}

/// Translation of a unit dual quaternion: 2 * dual * conj(real).
inline glm::dvec3 Translation(const DualQuat& d) {
  const glm::dquat t = 2.0 * (d.dual * glm::conjugate(d.real));
  return {t.x, t.y, t.z};
}

/// Cofactor matrix det(m) * inverse(m)^T, columns (b x c, c x a, a x b) of m = (a b c): it maps
/// normals like the inverse transpose, up to the sign of det, and stays defined (and of rank 2)
/// when m has rank 2.
inline glm::dmat3 Cofactor(const glm::dmat3& m) {
  return glm::dmat3(glm::cross(m[1], m[2]), glm::cross(m[2], m[0]), glm::cross(m[0], m[1]));
}

/// True if m is too close to singular to take its rotation (relative to its size).
inline bool NearlySingular(const glm::dmat3& m) {
  double size = 0.0;
  for (int c = 0; c < 3; ++c) size = std::fmax(size, glm::length(m[c]));
  return !(size > 0.0) || !(std::fabs(glm::determinant(m)) > 1e-9 * size * size * size);
}

/// The rotation of a non-singular 3x3 matrix by polar decomposition (Newton iteration on
/// (R + R^-T) / 2): m = rotation * stretch. A mirroring m (det < 0) gives the proper rotation
/// -R, leaving the reflection in the stretch.
inline glm::dmat3 PolarRotation(const glm::dmat3& m) {
  glm::dmat3 r = m;
  for (int i = 0; i < 30; ++i) {
    const glm::dmat3 next = 0.5 * (r + glm::transpose(glm::inverse(r)));
    double diff = 0.0;
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) diff = std::fmax(diff, std::fabs(next[c][k] - r[c][k]));
    r = next;
    if (diff < 1e-14) break;
  }
  if (glm::determinant(r) < 0.0) r = -r;
  return r;
}

/// Twist angle of rotation q about unit axis a (swing-twist decomposition q = swing * twist),
/// in (-pi, pi].
inline double TwistAngle(const glm::dquat& q, const glm::dvec3& a) {
  const double p = q.x * a.x + q.y * a.y + q.z * a.z;
  double w = q.w;
  double s = p;
  if (w < 0.0) {
    w = -w;
    s = -s;
  }
  return 2.0 * std::atan2(s, w);
}

/// Splits a skin matrix for DQS: its rigid part as a unit dual quaternion and its stretch
/// (M = [R t] * [S 0]). A (nearly) singular linear part, e.g. a joint scaled to 0 to hide what
/// it carries, has no rotation: R = identity and S = the linear part, which still gives M x
/// for a vertex on that joint alone. Returns true if the stretch differs from identity.
inline bool SplitSkinMatrix(const glm::dmat4& m, DualQuat* dq, glm::dmat3* stretch) {
  const glm::dmat3 linear(m);
  const glm::dmat3 r = NearlySingular(linear) ? glm::dmat3(1.0) : PolarRotation(linear);
  *stretch = glm::transpose(r) * linear;
  *dq = MakeDualQuat(glm::normalize(glm::quat_cast(r)), glm::dvec3(m[3]));
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 3; ++k)
      if (std::fabs((*stretch)[c][k] - (c == k ? 1.0 : 0.0)) > 1e-9) return true;
  return false;
}

/// Dual-quaternion skinning of one point (and normal, if `normal_out` is non-null): stretches
/// blended linearly and applied first, rigid parts blended in the hemisphere of the strongest
/// joint and normalised by the real part (Kavan et al. 2008, two-phase).
inline void DqsPoint(const DualQuat* dq, const glm::dmat3* stretch, bool has_stretch,
                     const VertexWeights& iw, const glm::dvec3& x_in, const glm::dvec3& n_in,
                     glm::dvec3* x_out, glm::dvec3* normal_out) {
  const glm::dvec4 w = NormalizedWeights(iw);
  int strongest = 0;
  for (int k = 1; k < 4; ++k)
    if (w[k] > w[strongest]) strongest = k;
  const glm::dquat pivot = dq[iw.joints[strongest]].real;
  glm::dquat real(0.0, 0.0, 0.0, 0.0), dual(0.0, 0.0, 0.0, 0.0);
  glm::dmat3 s(0.0);
  for (int k = 0; k < 4; ++k) {
    if (!(w[k] > 0.0)) continue;
    const DualQuat& d = dq[iw.joints[k]];
    const double sign = glm::dot(d.real, pivot) < 0.0 ? -1.0 : 1.0;
    real = real + (sign * w[k]) * d.real;
    dual = dual + (sign * w[k]) * d.dual;
    if (has_stretch) s += w[k] * stretch[iw.joints[k]];
  }
  const double len = glm::length(real);
  DualQuat b;
  b.real = real / len;
  b.dual = dual / len;
  glm::dvec3 x = x_in;
  if (has_stretch) x = s * x;
  *x_out = b.real * x + Translation(b);
  if (normal_out != nullptr) {
    glm::dvec3 n = n_in;
    if (has_stretch) n = Cofactor(s) * n * (glm::determinant(s) < 0.0 ? -1.0 : 1.0);
    n = b.real * n;
    const double l = glm::length(n);
    *normal_out = l > 0.0 ? n / l : n_in;
  }
}

}  // namespace dermis::deform

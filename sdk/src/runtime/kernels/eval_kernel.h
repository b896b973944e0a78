// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The fast evaluation kernel (docs/performance.md): the displaced, blended surface of Yoon
// Eq. 3-4 at one block of kPlanLanes samples of one control face, from the pose-independent
// data of an EvaluationPlan and the pose's packed patch coefficients.
//
// Included by one translation unit per instruction set (eval_kernel_generic.cpp,
// eval_kernel_avx2.cpp), each compiled with its own flags, over the portable SIMD layer
// simd.h (intrinsics per instruction set, a scalar fallback; no compiler vector extensions).
// Everything here therefore has internal linkage (an anonymous namespace), so no inline
// function of external linkage is ever compiled with two sets of flags.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "dermis/runtime/plan_layout.h"
#include "runtime/kernels/simd.h"

namespace dermis {
namespace plan_kernel {
namespace {

using simd::F;
using simd::Load;
using simd::M;
using simd::Select;
using simd::Splat;
using simd::Sqrt;

#define DERMIS_INLINE DERMIS_SIMD_INLINE

struct V3 {
  F x, y, z;
};

DERMIS_INLINE V3 Cross(const V3& a, const V3& b) {
  return V3{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
DERMIS_INLINE F Dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
DERMIS_INLINE V3 Add(const V3& a, const V3& b) { return V3{a.x + b.x, a.y + b.y, a.z + b.z}; }
DERMIS_INLINE V3 Sub(const V3& a, const V3& b) { return V3{a.x - b.x, a.y - b.y, a.z - b.z}; }
DERMIS_INLINE V3 Scale(const V3& a, F s) { return V3{a.x * s, a.y * s, a.z * s}; }
// a + s * b
DERMIS_INLINE V3 Madd(const V3& a, F s, const V3& b) {
  return V3{a.x + s * b.x, a.y + s * b.y, a.z + s * b.z};
}

// Everything one chart contributes at one block: chart surface S_a = P_a + d_a N_a and its
// chart derivatives (Eq. 3, the frame derivatives of local_patch.cpp), weighted by the
// partition of unity and mapped to face coordinates with the precomputed Jacobians.
template <bool kDisplaced>
DERMIS_INLINE void AccumulateCorner(const float* patch, const float* data, V3* s, V3* su, V3* sv) {
  const F x = Load(data + kFieldX * kPlanLanes);
  const F y = Load(data + kFieldY * kPlanLanes);
  const F two = Splat(2.0f);
  const F x2 = two * x, y2 = two * y;
  V3 p, px, py, pxx, pxy, pyy;
  F* pc[6][3] = {{&p.x, &p.y, &p.z},       {&px.x, &px.y, &px.z},    {&py.x, &py.y, &py.z},
                 {&pxx.x, &pxx.y, &pxx.z}, {&pxy.x, &pxy.y, &pxy.z}, {&pyy.x, &pyy.y, &pyy.z}};
  for (int k = 0; k < 3; ++k) {
    // Coefficient c_mn of coordinate k at patch[k * 9 + 3m + n]: P = sum c_mn x^m y^n.
    const float* c = patch + k * 9;
    const F c00 = Splat(c[0]), c01 = Splat(c[1]), c02 = Splat(c[2]);
    const F c10 = Splat(c[3]), c11 = Splat(c[4]), c12 = Splat(c[5]);
    const F c20 = Splat(c[6]), c21 = Splat(c[7]), c22 = Splat(c[8]);
    // A_m = sum_n c_mn y^n, B_m = dA_m/dy.
    const F a0 = c00 + y * (c01 + y * c02);
    const F a1 = c10 + y * (c11 + y * c12);
    const F a2 = c20 + y * (c21 + y * c22);
    const F b0 = c01 + y2 * c02;
    const F b1 = c11 + y2 * c12;
    const F b2 = c21 + y2 * c22;
    *pc[0][k] = a0 + x * (a1 + x * a2);
    *pc[1][k] = a1 + x2 * a2;
    *pc[2][k] = b0 + x * (b1 + x * b2);
    if (kDisplaced) {
      *pc[3][k] = two * a2;
      *pc[4][k] = b1 + x2 * b2;
      *pc[5][k] = two * (c02 + x * (c12 + x * c22));
    }
  }
  const V3 nr = Cross(px, py);
  const F l2 = Dot(nr, nr);
  // The patch is regular where |px x py| > 1e-6 |px| |py| (float's share of local_patch.cpp's
  // test); elsewhere the frame is the fallback normal with zero derivatives.
  const M ok = (l2 > Splat(1e-12f) * Dot(px, px) * Dot(py, py)) & (l2 > Splat(1e-30f));
  const F inv = Splat(1.0f) / Sqrt(Select(ok, l2, Splat(1.0f)));
  const V3 fb{Splat(patch[27]), Splat(patch[28]), Splat(patch[29])};
  const V3 n{Select(ok, nr.x * inv, fb.x), Select(ok, nr.y * inv, fb.y),
             Select(ok, nr.z * inv, fb.z)};
  V3 xp = p, xx = px, xy = py;
  if (kDisplaced) {
    const F d = Load(data + kFieldD * kPlanLanes);
    const F gx = Load(data + kFieldGx * kPlanLanes);
    const F gy = Load(data + kFieldGy * kPlanLanes);
    const V3 dnx = Add(Cross(pxx, py), Cross(px, pxy));
    const V3 dny = Add(Cross(pxy, py), Cross(px, pyy));
    const F zero = Splat(0.0f);
    const F invd = Select(ok, inv, zero) * d;
    // d * dN/dx = d (dn - N (N . dn)) / |n|
    const V3 nx = Scale(Sub(dnx, Scale(n, Dot(n, dnx))), invd);
    const V3 ny = Scale(Sub(dny, Scale(n, Dot(n, dny))), invd);
    xp = Madd(p, d, n);
    xx = Add(Madd(px, gx, n), nx);
    xy = Add(Madd(py, gy, n), ny);
  }
  const F w = Load(data + kFieldW * kPlanLanes);
  const F wu = Load(data + kFieldWu * kPlanLanes);
  const F wv = Load(data + kFieldWv * kPlanLanes);
  const F m00 = Load(data + kFieldM00 * kPlanLanes);
  const F m01 = Load(data + kFieldM01 * kPlanLanes);
  const F m10 = Load(data + kFieldM10 * kPlanLanes);
  const F m11 = Load(data + kFieldM11 * kPlanLanes);
  *s = Madd(*s, w, xp);
  *su = Madd(Madd(Madd(*su, wu, xp), m00, xx), m01, xy);
  *sv = Madd(Madd(Madd(*sv, wv, xp), m10, xx), m11, xy);
}

// Float pointer `bytes` bytes past `base`.
DERMIS_INLINE float* At(float* base, std::size_t bytes) {
  return reinterpret_cast<float*>(reinterpret_cast<unsigned char*>(base) + bytes);
}

// The optional per-lane outputs of one block (PlanOutputBuffers::tangents, ::derivatives):
// lane i's derivatives su, sv (d[0..5][i]) and unit normal nrm. The tangent is the sample's
// frame coefficients (a, b) applied to the derivatives, made orthogonal to the normal by one
// Gram-Schmidt step and normalised; where that vanishes (a degenerate surface), any unit
// vector orthogonal to the normal.
DERMIS_INLINE void WriteExtras(const PlanOutputBuffers& out, std::size_t index,
                               const float (&d)[6][kPlanLanes], int i, const float* nrm) {
  if (out.derivatives) {
    float* o = At(out.derivatives, index * out.derivative_stride);
    for (int k = 0; k < 6; ++k) o[k] = d[k][i];
  }
  if (out.tangents) {
    const float* c = out.tangent_frames + 4 * index;
    float t[3];
    for (int k = 0; k < 3; ++k) t[k] = c[0] * d[k][i] + c[1] * d[3 + k][i];
    const float tn = t[0] * nrm[0] + t[1] * nrm[1] + t[2] * nrm[2];
    for (int k = 0; k < 3; ++k) t[k] -= tn * nrm[k];
    float l2 = t[0] * t[0] + t[1] * t[1] + t[2] * t[2];
    if (!(l2 > 1e-30f)) {
      // The axis least aligned with the normal, made orthogonal to it.
      const float ax[3] = {std::fabs(nrm[0]), std::fabs(nrm[1]), std::fabs(nrm[2])};
      const int k0 = ax[0] <= ax[1] && ax[0] <= ax[2] ? 0 : (ax[1] <= ax[2] ? 1 : 2);
      for (int k = 0; k < 3; ++k) t[k] = (k == k0 ? 1.0f : 0.0f) - nrm[k0] * nrm[k];
      l2 = t[0] * t[0] + t[1] * t[1] + t[2] * t[2];
    }
    const float inv = 1.0f / std::sqrt(l2);
    float* o = At(out.tangents, index * out.tangent_stride);
    o[0] = t[0] * inv;
    o[1] = t[1] * inv;
    o[2] = t[2] * inv;
    o[3] = c[2];
  }
}

// Blocks [begin, end) of a plan into caller-owned strided float buffers.
DERMIS_INLINE void EvaluateBlocks(const PlanView& plan, const float* patches, std::size_t begin,
                                  std::size_t end, const PlanOutputBuffers& out) {
  for (std::size_t b = begin; b < end; ++b) {
    const PlanBlock& block = plan.blocks[b];
    const float* data = plan.data + b * kPlanBlockFloats;
    const F zero = Splat(0.0f);
    V3 s{zero, zero, zero}, su = s, sv = s;
    for (int a = 0; a < 4; ++a) {
      const std::int32_t v = block.chart[a];
      if (v < 0) continue;
      const float* patch = patches + static_cast<std::size_t>(v) * kPackedPatchStride;
      const float* corner = data + a * kPlanFields * kPlanLanes;
      if (block.displaced & (1u << a)) {
        AccumulateCorner<true>(patch, corner, &s, &su, &sv);
      } else {
        AccumulateCorner<false>(patch, corner, &s, &su, &sv);
      }
    }
    const V3 nr = Cross(su, sv);
    const F l2 = Dot(nr, nr);
    const M ok = l2 > Splat(1e-30f);
    const F inv = Splat(1.0f) / Sqrt(Select(ok, l2, Splat(1.0f)));
    const V3 n = Scale(nr, inv);
    float lanes[6][kPlanLanes];
    simd::Store(s.x, lanes[0]);
    simd::Store(s.y, lanes[1]);
    simd::Store(s.z, lanes[2]);
    simd::Store(n.x, lanes[3]);
    simd::Store(n.y, lanes[4]);
    simd::Store(n.z, lanes[5]);
    const unsigned ok_bits = simd::Bits(ok);
    const bool extras = out.tangents || out.derivatives;
    float d[6][kPlanLanes];
    if (extras) {
      simd::Store(su.x, d[0]);
      simd::Store(su.y, d[1]);
      simd::Store(su.z, d[2]);
      simd::Store(sv.x, d[3]);
      simd::Store(sv.y, d[4]);
      simd::Store(sv.z, d[5]);
    }
    for (int i = 0; i < block.count; ++i) {
      const std::size_t index = static_cast<std::size_t>(block.index[i]);
      float* pos = reinterpret_cast<float*>(reinterpret_cast<unsigned char*>(out.positions) +
                                            index * out.position_stride);
      pos[0] = lanes[0][i];
      pos[1] = lanes[1][i];
      pos[2] = lanes[2][i];
      // The lane's normal, or the dominant patch's where the blend's normal was degenerate.
      float nrm[3];
      if ((ok_bits >> i) & 1u) {
        nrm[0] = lanes[3][i];
        nrm[1] = lanes[4][i];
        nrm[2] = lanes[5][i];
      } else {
        const float* fb =
            patches + static_cast<std::size_t>(block.dominant[i]) * kPackedPatchStride + 27;
        nrm[0] = fb[0];
        nrm[1] = fb[1];
        nrm[2] = fb[2];
      }
      if (out.normals) {
        float* dst = reinterpret_cast<float*>(reinterpret_cast<unsigned char*>(out.normals) +
                                              index * out.normal_stride);
        dst[0] = nrm[0];
        dst[1] = nrm[1];
        dst[2] = nrm[2];
      }
      if (extras) WriteExtras(out, index, d, i, nrm);
    }
  }
}

#undef DERMIS_INLINE

}  // namespace
}  // namespace plan_kernel
}  // namespace dermis

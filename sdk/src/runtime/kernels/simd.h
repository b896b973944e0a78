// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The portable SIMD layer of the evaluation kernel (docs/performance.md, "Instruction sets"):
// two types of kPlanLanes (8) lanes, F (floats) and M (lane masks), and the few operations
// eval_kernel.h needs, written with each instruction set's standard intrinsics (no compiler
// vector extensions), with a plain scalar fallback:
//
//   AVX2 + FMA    one __m256 per F   (DERMIS_SIMD_AVX2, set by eval_kernel_avx2.cpp)
//   SSE2          two __m128         (every x86-64 CPU: the portable path there)
//   NEON          two float32x4_t    (every aarch64 CPU)
//   scalar        eight floats       (anything else, or DERMIS_SIMD_SCALAR)
//
// Hand-written rather than Highway (libhwy-dev): the kernel needs eight fixed lanes and eleven
// operations, and Highway's scalable vectors would make the lane count, hence the plan's
// block layout that the GPU shader shares, depend on the target. Every operation is IEEE
// single precision, lane by lane, so every backend computes the same values up to the
// compiler's contraction of a * b + c into a fused multiply-add where the target has one.
//
// Everything has internal linkage: each backend file compiles this header with its own flags.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#include "dermis/runtime/plan_layout.h"

#if !defined(DERMIS_SIMD_SCALAR)
#if defined(DERMIS_SIMD_AVX2)
#include <immintrin.h>
#define DERMIS_SIMD_IMPL_AVX2 1
#elif defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#define DERMIS_SIMD_IMPL_SSE2 1
#elif defined(__aarch64__) || defined(_M_ARM64)
#include <arm_neon.h>
#define DERMIS_SIMD_IMPL_NEON 1
#endif
#endif

#if defined(_MSC_VER) && !defined(__clang__)
#define DERMIS_SIMD_INLINE __forceinline
#else
#define DERMIS_SIMD_INLINE inline __attribute__((always_inline))
#endif

namespace dermis {
namespace simd {
namespace {

static_assert(kPlanLanes == 8, "the SIMD layer has 8 lanes");

#if defined(DERMIS_SIMD_IMPL_AVX2)

struct F {
  __m256 v;
};
struct M {
  __m256 v;
};
constexpr const char* kName = "avx2";
DERMIS_SIMD_INLINE F Splat(float x) { return F{_mm256_set1_ps(x)}; }
DERMIS_SIMD_INLINE F Load(const float* p) { return F{_mm256_loadu_ps(p)}; }
DERMIS_SIMD_INLINE void Store(F a, float* p) { _mm256_storeu_ps(p, a.v); }
DERMIS_SIMD_INLINE F operator+(F a, F b) { return F{_mm256_add_ps(a.v, b.v)}; }
DERMIS_SIMD_INLINE F operator-(F a, F b) { return F{_mm256_sub_ps(a.v, b.v)}; }
DERMIS_SIMD_INLINE F operator*(F a, F b) { return F{_mm256_mul_ps(a.v, b.v)}; }
DERMIS_SIMD_INLINE F operator/(F a, F b) { return F{_mm256_div_ps(a.v, b.v)}; }
DERMIS_SIMD_INLINE F Sqrt(F a) { return F{_mm256_sqrt_ps(a.v)}; }
DERMIS_SIMD_INLINE M operator>(F a, F b) { return M{_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ)}; }
DERMIS_SIMD_INLINE M operator&(M a, M b) { return M{_mm256_and_ps(a.v, b.v)}; }
/// mask ? b : c per lane.
DERMIS_SIMD_INLINE F Select(M mask, F b, F c) { return F{_mm256_blendv_ps(c.v, b.v, mask.v)}; }
/// Bit i set where lane i of the mask is.
DERMIS_SIMD_INLINE unsigned Bits(M m) { return static_cast<unsigned>(_mm256_movemask_ps(m.v)); }

#elif defined(DERMIS_SIMD_IMPL_SSE2)

struct F {
  __m128 lo, hi;
};
struct M {
  __m128 lo, hi;
};
constexpr const char* kName = "sse2";
DERMIS_SIMD_INLINE F Splat(float x) { return F{_mm_set1_ps(x), _mm_set1_ps(x)}; }
DERMIS_SIMD_INLINE F Load(const float* p) { return F{_mm_loadu_ps(p), _mm_loadu_ps(p + 4)}; }
DERMIS_SIMD_INLINE void Store(F a, float* p) {
  _mm_storeu_ps(p, a.lo);
  _mm_storeu_ps(p + 4, a.hi);
}
DERMIS_SIMD_INLINE F operator+(F a, F b) {
  return F{_mm_add_ps(a.lo, b.lo), _mm_add_ps(a.hi, b.hi)};
}
DERMIS_SIMD_INLINE F operator-(F a, F b) {
  return F{_mm_sub_ps(a.lo, b.lo), _mm_sub_ps(a.hi, b.hi)};
}
DERMIS_SIMD_INLINE F operator*(F a, F b) {
  return F{_mm_mul_ps(a.lo, b.lo), _mm_mul_ps(a.hi, b.hi)};
}
DERMIS_SIMD_INLINE F operator/(F a, F b) {
  return F{_mm_div_ps(a.lo, b.lo), _mm_div_ps(a.hi, b.hi)};
}
DERMIS_SIMD_INLINE F Sqrt(F a) { return F{_mm_sqrt_ps(a.lo), _mm_sqrt_ps(a.hi)}; }
DERMIS_SIMD_INLINE M operator>(F a, F b) {
  return M{_mm_cmpgt_ps(a.lo, b.lo), _mm_cmpgt_ps(a.hi, b.hi)};
}
DERMIS_SIMD_INLINE M operator&(M a, M b) {
  return M{_mm_and_ps(a.lo, b.lo), _mm_and_ps(a.hi, b.hi)};
}
DERMIS_SIMD_INLINE F Select(M m, F b, F c) {
  return F{_mm_or_ps(_mm_and_ps(m.lo, b.lo), _mm_andnot_ps(m.lo, c.lo)),
           _mm_or_ps(_mm_and_ps(m.hi, b.hi), _mm_andnot_ps(m.hi, c.hi))};
}
DERMIS_SIMD_INLINE unsigned Bits(M m) {
  return static_cast<unsigned>(_mm_movemask_ps(m.lo) | (_mm_movemask_ps(m.hi) << 4));
}

#elif defined(DERMIS_SIMD_IMPL_NEON)

struct F {
  float32x4_t lo, hi;
};
struct M {
  uint32x4_t lo, hi;
};
constexpr const char* kName = "neon";
DERMIS_SIMD_INLINE F Splat(float x) { return F{vdupq_n_f32(x), vdupq_n_f32(x)}; }
DERMIS_SIMD_INLINE F Load(const float* p) { return F{vld1q_f32(p), vld1q_f32(p + 4)}; }
DERMIS_SIMD_INLINE void Store(F a, float* p) {
  vst1q_f32(p, a.lo);
  vst1q_f32(p + 4, a.hi);
}
DERMIS_SIMD_INLINE F operator+(F a, F b) { return F{vaddq_f32(a.lo, b.lo), vaddq_f32(a.hi, b.hi)}; }
DERMIS_SIMD_INLINE F operator-(F a, F b) { return F{vsubq_f32(a.lo, b.lo), vsubq_f32(a.hi, b.hi)}; }
DERMIS_SIMD_INLINE F operator*(F a, F b) { return F{vmulq_f32(a.lo, b.lo), vmulq_f32(a.hi, b.hi)}; }
DERMIS_SIMD_INLINE F operator/(F a, F b) { return F{vdivq_f32(a.lo, b.lo), vdivq_f32(a.hi, b.hi)}; }
DERMIS_SIMD_INLINE F Sqrt(F a) { return F{vsqrtq_f32(a.lo), vsqrtq_f32(a.hi)}; }
DERMIS_SIMD_INLINE M operator>(F a, F b) { return M{vcgtq_f32(a.lo, b.lo), vcgtq_f32(a.hi, b.hi)}; }
DERMIS_SIMD_INLINE M operator&(M a, M b) { return M{vandq_u32(a.lo, b.lo), vandq_u32(a.hi, b.hi)}; }
DERMIS_SIMD_INLINE F Select(M m, F b, F c) {
  return F{vbslq_f32(m.lo, b.lo, c.lo), vbslq_f32(m.hi, b.hi, c.hi)};
}
DERMIS_SIMD_INLINE unsigned Bits(M m) {
  std::uint32_t lanes[8];
  vst1q_u32(lanes, m.lo);
  vst1q_u32(lanes + 4, m.hi);
  unsigned bits = 0;
  for (int i = 0; i < 8; ++i) bits |= (lanes[i] >> 31) << i;
  return bits;
}

#else  // scalar

struct F {
  float v[8];
};
struct M {
  bool v[8];
};
constexpr const char* kName = "scalar";
DERMIS_SIMD_INLINE F Splat(float x) { return F{{x, x, x, x, x, x, x, x}}; }
DERMIS_SIMD_INLINE F Load(const float* p) {
  F r;
  std::memcpy(r.v, p, sizeof(r.v));
  return r;
}
DERMIS_SIMD_INLINE void Store(F a, float* p) { std::memcpy(p, a.v, sizeof(a.v)); }
#define DERMIS_SIMD_LANEWISE(op)                           \
  DERMIS_SIMD_INLINE F operator op(F a, F b) {             \
    F r;                                                   \
    for (int i = 0; i < 8; ++i) r.v[i] = a.v[i] op b.v[i]; \
    return r;                                              \
  }
DERMIS_SIMD_LANEWISE(+)
DERMIS_SIMD_LANEWISE(-)
DERMIS_SIMD_LANEWISE(*)
DERMIS_SIMD_LANEWISE(/)
#undef DERMIS_SIMD_LANEWISE
DERMIS_SIMD_INLINE F Sqrt(F a) {
  F r;
  for (int i = 0; i < 8; ++i) r.v[i] = std::sqrt(a.v[i]);
  return r;
}
DERMIS_SIMD_INLINE M operator>(F a, F b) {
  M r;
  for (int i = 0; i < 8; ++i) r.v[i] = a.v[i] > b.v[i];
  return r;
}
DERMIS_SIMD_INLINE M operator&(M a, M b) {
  M r;
  for (int i = 0; i < 8; ++i) r.v[i] = a.v[i] && b.v[i];
  return r;
}
DERMIS_SIMD_INLINE F Select(M m, F b, F c) {
  F r;
  for (int i = 0; i < 8; ++i) r.v[i] = m.v[i] ? b.v[i] : c.v[i];
  return r;
}
DERMIS_SIMD_INLINE unsigned Bits(M m) {
  unsigned bits = 0;
  for (int i = 0; i < 8; ++i) bits |= static_cast<unsigned>(m.v[i]) << i;
  return bits;
}

#endif

}  // namespace
}  // namespace simd
}  // namespace dermis

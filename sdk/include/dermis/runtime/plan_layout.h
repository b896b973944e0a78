// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Memory layout of an EvaluationPlan as the evaluation kernels read it
/// (docs/performance.md, "The fast path"). Plain data, no dependencies: shared by the plan
/// builder and by every instruction-set variant of the kernel.
#pragma once

#include <cstddef>
#include <cstdint>

namespace dermis {

/// Samples per block (one SIMD register of floats on AVX2).
constexpr int kPlanLanes = 8;

/// Per-corner fields of a block, each kPlanLanes floats: chart point (x, y), displacement value
/// and gradient (d, gx, gy), weight psi and its face derivatives (psi_u, psi_v), and the
/// weighted chart-to-face Jacobian psi * dz/d(u, v) (m00 = psi dx/du, m01 = psi dy/du,
/// m10 = psi dx/dv, m11 = psi dy/dv). In the one-chart region of a corner (docs/notes/manifold.md
/// section 6) psi = 1 and the Jacobian is the identity: the normal is then taken from the
/// chart derivatives themselves, as the scalar evaluator does.
enum PlanField : int {
  kFieldX = 0,
  kFieldY,
  kFieldD,
  kFieldGx,
  kFieldGy,
  kFieldW,
  kFieldWu,
  kFieldWv,
  kFieldM00,
  kFieldM01,
  kFieldM10,
  kFieldM11,
  kPlanFields
};

/// Floats of one block: 4 corners x kPlanFields x kPlanLanes.
constexpr std::size_t kPlanBlockFloats = 4 * kPlanFields * kPlanLanes;

/// Floats per packed patch in the buffer PackPatches() writes: 27 coefficients
/// (coordinate-major, c_mn at 9k + 3m + n), the fallback normal, 2 of padding.
constexpr std::size_t kPackedPatchStride = 32;

/// One block: up to kPlanLanes samples of one control face.
struct PlanBlock {
  std::int32_t chart[4];              ///< Vertex of each face corner, or -1 where no lane uses it.
  std::int32_t index[kPlanLanes];     ///< Output index of each lane.
  std::int32_t dominant[kPlanLanes];  ///< Vertex whose fallback normal a degenerate lane takes.
  std::int32_t count;                 ///< Lanes in use (the rest repeat lane 0).
  std::uint32_t displaced;            ///< Bit a: corner a has a non-zero displacement somewhere.
};

/// What the kernels read.
struct PlanView {
  const PlanBlock* blocks;
  const float* data;  ///< kPlanBlockFloats per block.
};

/// Caller-owned output of EvaluatePlan() and of every kernel: sample i's position (3 floats)
/// at positions + i * position_stride bytes, its unit normal likewise (normals may be null).
/// The optional outputs below cost nothing when null (CPU kernels only; the GPU shader writes
/// positions and normals).
struct PlanOutputBuffers {
  float* positions = nullptr;
  std::size_t position_stride = 3 * sizeof(float);
  float* normals = nullptr;
  std::size_t normal_stride = 3 * sizeof(float);
  /// Tangents: 4 floats per sample (unit xyz orthogonal to the normal, w = the handedness) at
  /// tangents + i * tangent_stride bytes. Needs `tangent_frames`: 4 floats per sample
  /// (a, b, w, unused), the tangent being a dS/du + b dS/dv (face coordinates) made orthogonal
  /// to the normal and normalised (docs/engine-integration.md, "Tangents").
  float* tangents = nullptr;
  std::size_t tangent_stride = 4 * sizeof(float);
  const float* tangent_frames = nullptr;
  /// First derivatives dS/du then dS/dv of the displaced surface in the face's (u, v)
  /// (6 floats per sample) at derivatives + i * derivative_stride bytes.
  float* derivatives = nullptr;
  std::size_t derivative_stride = 6 * sizeof(float);
};

}  // namespace dermis

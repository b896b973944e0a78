// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Precomputed evaluation of a displaced surface at fixed sample locations (topology
/// once, positions per frame): everything of Yoon Eq. 3-4 that does not depend on the pose --
/// chart coordinates, partition-of-unity weights and their derivatives, chart Jacobians and
/// displacement values -- is computed once per (face, u, v) sample and chart and stored in
/// float, grouped by control face in SIMD blocks. Per frame only the packed patch
/// coefficients change (PackPatches()), and EvaluatePlan() runs the blended displaced surface,
/// its derivatives and unit normals with no allocation. The scalar reference is
/// EvaluateSurface() (surface_evaluator.h); the fast path agrees with it within float
/// rounding (test `runtime: the fast path equals the scalar reference`, docs/performance.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/runtime/plan_layout.h"
#include "dermis/surface/displacement.h"
#include "dermis/surface/local_patch.h"
#include "dermis/surface/manifold_domain.h"
#include "dermis/surface/tessellation.h"

namespace dermis {

/// Instruction set of the evaluation kernel.
enum class SimdPath : std::uint8_t {
  kAuto = 0,     ///< The best one this CPU has.
  kGeneric = 1,  ///< The portable SIMD path: SSE2 on x86-64, NEON on aarch64, else scalar.
  kAvx2 = 2,     ///< AVX2 + FMA (x86-64 only).
  kScalar = 3,   ///< The same kernel lane by lane in plain C++ (every CPU; the fallback).
};

/// The path kAuto resolves to on this CPU.
SimdPath BestSimdPath();
/// Whether this CPU (and build) can run `path`.
bool SimdPathAvailable(SimdPath path);
/// "generic", "avx2", "scalar" (kAuto: the resolved one).
const char* SimdPathName(SimdPath path);

/// Packs `count` local patches into the kernel's float layout (27 coefficients and the
/// fallback normal per patch, kPackedPatchStride floats each) into caller-owned `out`
/// (count * kPackedPatchStride floats). Does not allocate.
void PackPatches(const LocalPatch* patches, std::size_t count, float* out);

/// Options of EvaluationPlan::Build().
struct EvaluationPlanOptions {
  int threads = 1;  ///< Threads for the precomputation (0: all cores); results do not vary.
};

/// Pose-independent per-sample data of one surface at a fixed list of sample locations.
/// Immutable after Build(); thread-shareable.
class EvaluationPlan {
 public:
  EvaluationPlan();
  ~EvaluationPlan();
  EvaluationPlan(EvaluationPlan&&) noexcept;
  EvaluationPlan& operator=(EvaluationPlan&&) noexcept;
  EvaluationPlan(const EvaluationPlan&) = delete;
  EvaluationPlan& operator=(const EvaluationPlan&) = delete;

  /// Precomputes samples[0 .. count) of `domain` with displacement `displacement` (null: the
  /// domain surface; a TruncatedDisplacement gives fewer levels). Output index i of
  /// EvaluatePlan() is samples[i]. Fails on an invalid location (face out of range, uv
  /// outside [0, 1]^2 or not finite), naming the sample. Keeps no pointer to its arguments.
  static Status Build(const ManifoldDomain& domain, const Displacement* displacement,
                      const SampleLocation* samples, std::size_t count,
                      const EvaluationPlanOptions& options, EvaluationPlan* out);

  std::size_t num_samples() const { return num_samples_; }
  std::size_t num_vertices() const { return num_vertices_; }  ///< Of the domain.
  /// Blocks of up to 8 samples of one face; EvaluatePlan() runs any sub-range of them.
  std::size_t num_blocks() const { return blocks_.size(); }
  /// Bytes held by the plan.
  std::size_t memory_bytes() const;

  const PlanBlock* blocks() const { return blocks_.data(); }
  const float* block_data() const { return data_.data(); }

 private:
  std::size_t num_samples_ = 0;
  std::size_t num_vertices_ = 0;
  std::vector<PlanBlock> blocks_;
  std::vector<float> data_;
};

/// Evaluates blocks [block_begin, block_end) of `plan` with the pose's packed patches
/// (plan.num_vertices() * kPackedPatchStride floats from PackPatches()). Positions are in the
/// patches' units; normals are unit length, from the dominant corner chart's fallback normal
/// where the surface is degenerate. Disjoint block ranges may run concurrently; no allocation,
/// no exceptions. Returns false (writing nothing) if the range or buffers are invalid or the
/// path is not available.
bool EvaluatePlan(const EvaluationPlan& plan, const float* packed_patches, std::size_t block_begin,
                  std::size_t block_end, const PlanOutputBuffers& out,
                  SimdPath path = SimdPath::kAuto);

}  // namespace dermis

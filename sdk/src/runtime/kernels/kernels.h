// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The CPU backends of the evaluation kernel (docs/performance.md, "The fast path"). Every
// backend is one file in this folder that compiles eval_kernel.h with its own instruction-set
// flags and defines one entry point of the one signature below; backends.cpp lists them with
// the test of whether the CPU runs them. A new backend: docs/overview.md.
#pragma once

#include <cstddef>

#include "dermis/runtime/evaluation_plan.h"
#include "dermis/runtime/plan_layout.h"

namespace dermis::kernels {

/// The signature of every backend: evaluates blocks [begin, end) of `plan` with the pose's
/// packed patches (kPackedPatchStride floats per control vertex) into `out`. Checks nothing,
/// allocates nothing; the caller (EvaluatePlan) has validated the arguments.
using EvaluateBlocksFn = void (*)(const PlanView& plan, const float* patches, std::size_t begin,
                                  std::size_t end, const PlanOutputBuffers& out);

/// One backend compiled into this build.
struct Backend {
  SimdPath path;
  EvaluateBlocksFn evaluate;
  bool (*available)();  ///< Whether this CPU runs it.
};

/// The backends compiled in, from the portable one to the fastest; `*count` their number.
const Backend* Backends(std::size_t* count);

/// The backend of `path` if it is compiled in and this CPU runs it (kAuto: the fastest such),
/// else null.
const Backend* FindBackend(SimdPath path);

/// Entry points, one per backend file.
void EvaluateBlocksScalar(const PlanView& plan, const float* patches, std::size_t begin,
                          std::size_t end, const PlanOutputBuffers& out);
void EvaluateBlocksGeneric(const PlanView& plan, const float* patches, std::size_t begin,
                           std::size_t end, const PlanOutputBuffers& out);
#if defined(__x86_64__)
void EvaluateBlocksAvx2(const PlanView& plan, const float* patches, std::size_t begin,
                        std::size_t end, const PlanOutputBuffers& out);
#endif

}  // namespace dermis::kernels

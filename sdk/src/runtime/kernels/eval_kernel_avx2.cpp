// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The evaluation kernel (eval_kernel.h) compiled for one instruction set: avx2.
#define DERMIS_SIMD_AVX2 1
#include "runtime/kernels/eval_kernel.h"
#include "runtime/kernels/kernels.h"

namespace dermis::kernels {

void EvaluateBlocksAvx2(const PlanView& plan, const float* patches, std::size_t begin,
                        std::size_t end, const PlanOutputBuffers& out) {
  plan_kernel::EvaluateBlocks(plan, patches, begin, end, out);
}

}  // namespace dermis::kernels

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The SPIR-V of shaders/evaluate_plan.comp, compiled at build time by glslc (sdk/CMakeLists.txt
// writes evaluate_plan.spv.inc, the words as a C initializer list).
#include "dermis/gpu/shader_interface.h"

namespace dermis {
namespace gpu {

namespace {
const std::uint32_t kEvaluatePlanSpirv[] = {
#include "evaluate_plan.spv.inc"
};
}  // namespace

const std::uint32_t* EvaluateShaderSpirv(std::size_t* word_count) {
  if (word_count) *word_count = sizeof(kEvaluatePlanSpirv) / sizeof(kEvaluatePlanSpirv[0]);
  return kEvaluatePlanSpirv;
}

}  // namespace gpu
}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The interface of the GPU evaluation shader (`evaluate_plan.comp`, docs/gpu.md): its
/// descriptor bindings, specialization constants, push constants, dispatch arithmetic and the
/// SPIR-V words compiled into the library. Plain data, no Vulkan types: an engine that creates
/// its own pipeline needs this header and docs/gpu.md, nothing else of Dermis' GPU host code.
#pragma once

#include <cstddef>
#include <cstdint>

#include "dermis/runtime/plan_layout.h"

namespace dermis {
namespace gpu {

/// Descriptor set 0, every binding a storage buffer (VK_DESCRIPTOR_TYPE_STORAGE_BUFFER),
/// visible to the compute stage.
enum Binding : std::uint32_t {
  kBindingPlanBlocks = 0,  ///< PlanBlock[] of the plan (read).
  kBindingPlanData = 1,    ///< The plan's block floats, kPlanBlockFloats per block (read).
  kBindingPatches = 2,     ///< Packed patches, kPackedPatchStride per control vertex (read).
  kBindingPositions = 3,   ///< The positions' vertex buffer (written: 3 floats per vertex).
  kBindingNormals = 4,     ///< The normals' vertex buffer (written when normal_stride != 0).
  kBindingCount = 5
};

/// Specialization constants of the pipeline.
enum SpecConstant : std::uint32_t {
  kSpecLanes = 0,          ///< uint: samples per plan block; must be kPlanLanes.
  kSpecWorkgroupSize = 1,  ///< uint: local_size_x (default kDefaultWorkgroupSize).
};

/// The shader's local_size_x when specialization constant 1 is not set.
constexpr std::uint32_t kDefaultWorkgroupSize = 64;

/// Push constants (VK_SHADER_STAGE_COMPUTE_BIT, offset 0, 24 bytes). Byte offsets and strides
/// must be multiples of 4; strides at least 12.
struct PushConstants {
  std::uint32_t block_begin;      ///< First block of the dispatch, relative to binding 0's range.
  std::uint32_t block_end;        ///< One past the last block, likewise.
  std::uint32_t position_offset;  ///< Bytes into binding 3's range of output vertex 0's position.
  std::uint32_t position_stride;  ///< Bytes between consecutive vertices' positions.
  std::uint32_t normal_offset;    ///< Bytes into binding 4's range of output vertex 0's normal.
  std::uint32_t normal_stride;    ///< Bytes between normals; 0 writes no normals.
};
static_assert(sizeof(PushConstants) == 24, "push constants are 6 uints");

/// Bytes of one PlanBlock in binding 0 (4 + 2 kPlanLanes + 2 32-bit words).
constexpr std::size_t kPlanBlockBytes = sizeof(PlanBlock);
static_assert(kPlanBlockBytes == 4 * (4 + 2 * kPlanLanes + 2), "PlanBlock has padding");
/// Bytes of one block's floats in binding 1.
constexpr std::size_t kPlanBlockDataBytes = kPlanBlockFloats * sizeof(float);
/// Bytes of one control vertex's packed patch in binding 2.
constexpr std::size_t kPackedPatchBytes = kPackedPatchStride * sizeof(float);

/// Workgroups that evaluate `blocks` plan blocks: one invocation per lane of every block.
constexpr std::uint64_t WorkgroupCount(std::uint64_t blocks,
                                       std::uint32_t workgroup_size = kDefaultWorkgroupSize) {
  return (blocks * kPlanLanes + workgroup_size - 1) / workgroup_size;
}

/// The SPIR-V of evaluate_plan.comp (compiled at build time by glslc for Vulkan 1.0, the same
/// words as the installed `share/dermis/shaders/evaluate_plan.spv`); `*word_count` receives
/// the number of 32-bit words. Entry point "main".
const std::uint32_t* EvaluateShaderSpirv(std::size_t* word_count);

}  // namespace gpu
}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Vulkan results as Status messages (internal to dermis::gpu).
#pragma once

#include <vulkan/vulkan_core.h>

#include <string>

#include "dermis/core/status.h"

namespace dermis {
namespace gpu {

inline const char* VkResultName(VkResult r) {
  switch (r) {
    case VK_SUCCESS:
      return "VK_SUCCESS";
    case VK_NOT_READY:
      return "VK_NOT_READY";
    case VK_TIMEOUT:
      return "VK_TIMEOUT";
    case VK_INCOMPLETE:
      return "VK_INCOMPLETE";
    case VK_ERROR_OUT_OF_HOST_MEMORY:
      return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
      return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED:
      return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST:
      return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED:
      return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT:
      return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT:
      return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT:
      return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER:
      return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS:
      return "VK_ERROR_TOO_MANY_OBJECTS";
    case VK_ERROR_FORMAT_NOT_SUPPORTED:
      return "VK_ERROR_FORMAT_NOT_SUPPORTED";
    case VK_ERROR_FRAGMENTED_POOL:
      return "VK_ERROR_FRAGMENTED_POOL";
    case VK_ERROR_OUT_OF_POOL_MEMORY:
      return "VK_ERROR_OUT_OF_POOL_MEMORY";
    default:
      return "VkResult error";
  }
}

/// Status for a failed Vulkan call: "vkCreateDevice failed: VK_ERROR_... (-3)" (`call` may be
/// the whole call expression; the name is what precedes its first parenthesis).
inline Status VkFailure(const char* call, VkResult r) {
  std::string name(call);
  name = name.substr(0, name.find('('));
  const StatusCode code = r == VK_ERROR_OUT_OF_HOST_MEMORY || r == VK_ERROR_OUT_OF_DEVICE_MEMORY
                              ? StatusCode::kUnsupported
                              : StatusCode::kInternal;
  return Status(code, name + " failed: " + VkResultName(r) + " (" +
                          std::to_string(static_cast<int>(r)) + ")");
}

}  // namespace gpu
}  // namespace dermis

// Returns a Status from the enclosing function when a Vulkan call fails.
#define DERMIS_VK(call)                                          \
  do {                                                           \
    const VkResult dermis_vk_result_ = (call);                   \
    if (dermis_vk_result_ != VK_SUCCESS)                         \
      return ::dermis::gpu::VkFailure(#call, dermis_vk_result_); \
  } while (0)

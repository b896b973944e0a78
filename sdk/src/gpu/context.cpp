// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The Vulkan context of dermis::gpu (docs/gpu.md): instance (optionally with the Khronos
// validation layer), the choice of a physical device with a compute queue, the logical device,
// the compute pipeline of evaluate_plan.comp, and one-shot submissions with timestamps.
#include <algorithm>
#include <cstring>
#include <mutex>
#include <vector>

#include "dermis/gpu/gpu.h"
#include "gpu/vk_result.h"

namespace dermis {
namespace gpu {

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
constexpr std::uint64_t kFenceTimeoutNs = 120ull * 1000 * 1000 * 1000;

std::mutex& ValidationMutex() {
  static std::mutex m;
  return m;
}

bool HasInstanceExtension(const std::vector<VkExtensionProperties>& all, const char* name) {
  for (const VkExtensionProperties& e : all) {
    if (std::strcmp(e.extensionName, name) == 0) return true;
  }
  return false;
}

// Lower is better: the device type order of ContextOptions::device_index = -1.
int TypeRank(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return 3;
    default:
      return 4;
  }
}

// The first queue family with compute, or -1.
int ComputeFamily(VkPhysicalDevice device) {
  std::uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  for (std::uint32_t i = 0; i < count; ++i) {
    if (families[i].queueCount > 0 && (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

}  // namespace

VKAPI_ATTR VkBool32 VKAPI_CALL Context::OnValidation(
    VkDebugUtilsMessageSeverityFlagBitsEXT /*severity*/, VkDebugUtilsMessageTypeFlagsEXT /*types*/,
    const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  Context* c = static_cast<Context*>(user);
  const char* message = data && data->pMessage ? data->pMessage : "(no message)";
  std::lock_guard<std::mutex> lock(ValidationMutex());
  ++c->validation_messages_;
  c->last_validation_message_ = message;
  if (c->validation_callback_) c->validation_callback_(message, c->validation_user_);
  return VK_FALSE;
}

const char* Context::device_type() const {
  switch (device_type_) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "cpu";
    default:
      return "other";
  }
}

Context::~Context() {
  if (device_ != VK_NULL_HANDLE) {
    vkDeviceWaitIdle(device_);
    if (pipeline_) vkDestroyPipeline(device_, pipeline_, nullptr);
    if (pipeline_layout_) vkDestroyPipelineLayout(device_, pipeline_layout_, nullptr);
    if (set_layout_) vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
    if (shader_) vkDestroyShaderModule(device_, shader_, nullptr);
    if (query_pool_) vkDestroyQueryPool(device_, query_pool_, nullptr);
    if (fence_) vkDestroyFence(device_, fence_, nullptr);
    if (command_pool_) vkDestroyCommandPool(device_, command_pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (messenger_ != VK_NULL_HANDLE) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
  }
  if (instance_ != VK_NULL_HANDLE) vkDestroyInstance(instance_, nullptr);
}

Status Context::Create(const ContextOptions& options, std::unique_ptr<Context>* out) {
  if (!out) return Status::InvalidInput("gpu::Context::Create: no output");
  std::unique_ptr<Context> c(new Context());
  c->validation_callback_ = options.validation_callback;
  c->validation_user_ = options.validation_user;

  // Instance: Vulkan 1.0, portability enumeration where the loader offers it (MoltenVK), the
  // validation layer and debug utils when asked for and installed.
  std::uint32_t count = 0;
  VkResult r = vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr);
  if (r != VK_SUCCESS) {
    return Status::Unsupported(std::string("no usable Vulkan loader: ") + VkResultName(r));
  }
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateInstanceExtensionProperties(nullptr, &count, extensions.data());
  std::vector<const char*> enabled;
  VkInstanceCreateFlags flags = 0;
#ifdef VK_KHR_portability_enumeration
  if (HasInstanceExtension(extensions, VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME)) {
    enabled.push_back(VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME);
    flags |= VK_INSTANCE_CREATE_ENUMERATE_PORTABILITY_BIT_KHR;
    // A portability device's VK_KHR_portability_subset requires this one.
    if (HasInstanceExtension(extensions, VK_KHR_GET_PHYSICAL_DEVICE_PROPERTIES_2_EXTENSION_NAME)) {
      enabled.push_back(VK_KHR_GET_PHYSICAL_DEVICE_PROPERTIES_2_EXTENSION_NAME);
    }
  }
#endif
  std::vector<const char*> layers;
  bool debug_utils = false;
  if (options.validation) {
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> all(count);
    vkEnumerateInstanceLayerProperties(&count, all.data());
    for (const VkLayerProperties& l : all) {
      if (std::strcmp(l.layerName, kValidationLayer) == 0) layers.push_back(kValidationLayer);
    }
    // VK_EXT_debug_utils comes from the loader or from the layer itself.
    std::vector<VkExtensionProperties> layer_extensions;
    if (!layers.empty()) {
      vkEnumerateInstanceExtensionProperties(kValidationLayer, &count, nullptr);
      layer_extensions.resize(count);
      vkEnumerateInstanceExtensionProperties(kValidationLayer, &count, layer_extensions.data());
    }
    if (!layers.empty() &&
        (HasInstanceExtension(extensions, VK_EXT_DEBUG_UTILS_EXTENSION_NAME) ||
         HasInstanceExtension(layer_extensions, VK_EXT_DEBUG_UTILS_EXTENSION_NAME))) {
      enabled.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
      debug_utils = true;
    }
  }
  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "dermis";
  app.pEngineName = "dermis";
  app.apiVersion = VK_API_VERSION_1_0;
  VkInstanceCreateInfo ici{};
  ici.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  ici.flags = flags;
  ici.pApplicationInfo = &app;
  ici.enabledExtensionCount = static_cast<std::uint32_t>(enabled.size());
  ici.ppEnabledExtensionNames = enabled.data();
  ici.enabledLayerCount = debug_utils ? static_cast<std::uint32_t>(layers.size()) : 0u;
  ici.ppEnabledLayerNames = layers.data();
  r = vkCreateInstance(&ici, nullptr, &c->instance_);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER) {
    return Status::Unsupported(
        "no Vulkan driver (vkCreateInstance: VK_ERROR_INCOMPATIBLE_DRIVER); on Debian, "
        "mesa-vulkan-drivers provides lavapipe, a CPU implementation");
  }
  if (r != VK_SUCCESS) return VkFailure("vkCreateInstance", r);
  if (debug_utils) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(c->instance_, "vkCreateDebugUtilsMessengerEXT"));
    if (create) {
      VkDebugUtilsMessengerCreateInfoEXT mi{};
      mi.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
      mi.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
      mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
      mi.pfnUserCallback = &Context::OnValidation;
      mi.pUserData = c.get();
      DERMIS_VK(create(c->instance_, &mi, nullptr, &c->messenger_));
    }
  }

  // Physical device.
  r = vkEnumeratePhysicalDevices(c->instance_, &count, nullptr);
  if (r != VK_SUCCESS) return VkFailure("vkEnumeratePhysicalDevices", r);
  std::vector<VkPhysicalDevice> devices(count);
  if (count > 0) DERMIS_VK(vkEnumeratePhysicalDevices(c->instance_, &count, devices.data()));
  if (devices.empty()) {
    return Status::Unsupported(
        "no Vulkan device; on Debian, mesa-vulkan-drivers provides lavapipe, a CPU "
        "implementation");
  }
  int chosen = -1, family = -1;
  if (options.device_index >= 0) {
    if (static_cast<std::size_t>(options.device_index) >= devices.size()) {
      return Status::InvalidInput("Vulkan device " + std::to_string(options.device_index) +
                                  " requested, the machine has " + std::to_string(devices.size()));
    }
    chosen = options.device_index;
    family = ComputeFamily(devices[static_cast<std::size_t>(chosen)]);
    if (family < 0) {
      return Status::Unsupported("Vulkan device " + std::to_string(chosen) +
                                 " has no compute queue");
    }
  } else {
    int best_rank = 99;
    for (std::size_t i = 0; i < devices.size(); ++i) {
      const int f = ComputeFamily(devices[i]);
      if (f < 0) continue;
      VkPhysicalDeviceProperties p;
      vkGetPhysicalDeviceProperties(devices[i], &p);
      const int rank = TypeRank(p.deviceType);
      if (rank < best_rank) {
        best_rank = rank;
        chosen = static_cast<int>(i);
        family = f;
      }
    }
    if (chosen < 0) return Status::Unsupported("no Vulkan device has a compute queue");
  }
  c->physical_ = devices[static_cast<std::size_t>(chosen)];
  c->queue_family_ = static_cast<std::uint32_t>(family);
  VkPhysicalDeviceProperties props;
  vkGetPhysicalDeviceProperties(c->physical_, &props);
  c->limits_ = props.limits;
  c->device_type_ = props.deviceType;
  c->device_name_ = props.deviceName;
  vkGetPhysicalDeviceMemoryProperties(c->physical_, &c->memory_);
  {
    std::uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(c->physical_, &n, nullptr);
    std::vector<VkQueueFamilyProperties> families(n);
    vkGetPhysicalDeviceQueueFamilyProperties(c->physical_, &n, families.data());
    const std::uint32_t bits = families[c->queue_family_].timestampValidBits;
    if (bits > 0 && props.limits.timestampPeriod > 0.0f) {
      c->timestamp_period_ns_ = static_cast<double>(props.limits.timestampPeriod);
      c->timestamp_mask_ = bits >= 64 ? ~0ull : ((1ull << bits) - 1ull);
    }
  }

  // Logical device: one compute queue; VK_KHR_portability_subset where the device has it (the
  // specification requires enabling it then).
  std::vector<const char*> device_extensions;
  {
    std::uint32_t n = 0;
    vkEnumerateDeviceExtensionProperties(c->physical_, nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> all(n);
    vkEnumerateDeviceExtensionProperties(c->physical_, nullptr, &n, all.data());
    if (HasInstanceExtension(all, "VK_KHR_portability_subset")) {
      device_extensions.push_back("VK_KHR_portability_subset");
    }
  }
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo qi{};
  qi.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  qi.queueFamilyIndex = c->queue_family_;
  qi.queueCount = 1;
  qi.pQueuePriorities = &priority;
  VkDeviceCreateInfo di{};
  di.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  di.queueCreateInfoCount = 1;
  di.pQueueCreateInfos = &qi;
  di.enabledExtensionCount = static_cast<std::uint32_t>(device_extensions.size());
  di.ppEnabledExtensionNames = device_extensions.data();
  DERMIS_VK(vkCreateDevice(c->physical_, &di, nullptr, &c->device_));
  vkGetDeviceQueue(c->device_, c->queue_family_, 0, &c->queue_);

  VkCommandPoolCreateInfo pi{};
  pi.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pi.queueFamilyIndex = c->queue_family_;
  DERMIS_VK(vkCreateCommandPool(c->device_, &pi, nullptr, &c->command_pool_));
  VkCommandBufferAllocateInfo ai{};
  ai.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  ai.commandPool = c->command_pool_;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  DERMIS_VK(vkAllocateCommandBuffers(c->device_, &ai, &c->command_buffer_));
  VkFenceCreateInfo fi{};
  fi.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  DERMIS_VK(vkCreateFence(c->device_, &fi, nullptr, &c->fence_));
  if (c->has_timestamps()) {
    VkQueryPoolCreateInfo qpi{};
    qpi.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
    qpi.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qpi.queryCount = 2;
    DERMIS_VK(vkCreateQueryPool(c->device_, &qpi, nullptr, &c->query_pool_));
  }
  const Status s = c->CreatePipeline();
  if (!s.ok()) return s;
  *out = std::move(c);
  return Status::Ok();
}

Status Context::CreatePipeline() {
  std::size_t words = 0;
  const std::uint32_t* code = EvaluateShaderSpirv(&words);
  VkShaderModuleCreateInfo si{};
  si.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
  si.codeSize = words * sizeof(std::uint32_t);
  si.pCode = code;
  DERMIS_VK(vkCreateShaderModule(device_, &si, nullptr, &shader_));

  VkDescriptorSetLayoutBinding bindings[kBindingCount];
  for (std::uint32_t b = 0; b < kBindingCount; ++b) {
    bindings[b] = VkDescriptorSetLayoutBinding{};
    bindings[b].binding = b;
    bindings[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    bindings[b].descriptorCount = 1;
    bindings[b].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  VkDescriptorSetLayoutCreateInfo li{};
  li.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
  li.bindingCount = kBindingCount;
  li.pBindings = bindings;
  DERMIS_VK(vkCreateDescriptorSetLayout(device_, &li, nullptr, &set_layout_));
  VkPushConstantRange range{};
  range.stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  range.offset = 0;
  range.size = sizeof(PushConstants);
  VkPipelineLayoutCreateInfo pli{};
  pli.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
  pli.setLayoutCount = 1;
  pli.pSetLayouts = &set_layout_;
  pli.pushConstantRangeCount = 1;
  pli.pPushConstantRanges = &range;
  DERMIS_VK(vkCreatePipelineLayout(device_, &pli, nullptr, &pipeline_layout_));

  // Specialization: the plan's lane count and a workgroup the device allows.
  workgroup_size_ =
      std::min<std::uint32_t>({kDefaultWorkgroupSize, limits_.maxComputeWorkGroupSize[0],
                               limits_.maxComputeWorkGroupInvocations});
  const std::uint32_t spec_values[2] = {static_cast<std::uint32_t>(kPlanLanes), workgroup_size_};
  const VkSpecializationMapEntry entries[2] = {
      {kSpecLanes, 0, sizeof(std::uint32_t)},
      {kSpecWorkgroupSize, sizeof(std::uint32_t), sizeof(std::uint32_t)}};
  VkSpecializationInfo spec{};
  spec.mapEntryCount = 2;
  spec.pMapEntries = entries;
  spec.dataSize = sizeof(spec_values);
  spec.pData = spec_values;
  VkComputePipelineCreateInfo ci{};
  ci.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
  ci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  ci.stage.module = shader_;
  ci.stage.pName = "main";
  ci.stage.pSpecializationInfo = &spec;
  ci.layout = pipeline_layout_;
  DERMIS_VK(vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &ci, nullptr, &pipeline_));
  return Status::Ok();
}

Status Context::SubmitRecorded(void (*record)(VkCommandBuffer, void*), void* user,
                               double* device_seconds) {
  if (!record) return Status::InvalidInput("gpu::Context::Submit: nothing to record");
  if (device_seconds) *device_seconds = -1.0;
  const bool timed = device_seconds && query_pool_ != VK_NULL_HANDLE;
  DERMIS_VK(vkResetCommandBuffer(command_buffer_, 0));
  VkCommandBufferBeginInfo bi{};
  bi.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  DERMIS_VK(vkBeginCommandBuffer(command_buffer_, &bi));
  if (timed) {
    vkCmdResetQueryPool(command_buffer_, query_pool_, 0, 2);
    vkCmdWriteTimestamp(command_buffer_, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, query_pool_, 0);
  }
  record(command_buffer_, user);
  if (timed) {
    vkCmdWriteTimestamp(command_buffer_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, query_pool_, 1);
  }
  DERMIS_VK(vkEndCommandBuffer(command_buffer_));
  VkSubmitInfo si{};
  si.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  si.commandBufferCount = 1;
  si.pCommandBuffers = &command_buffer_;
  DERMIS_VK(vkResetFences(device_, 1, &fence_));
  DERMIS_VK(vkQueueSubmit(queue_, 1, &si, fence_));
  const VkResult r = vkWaitForFences(device_, 1, &fence_, VK_TRUE, kFenceTimeoutNs);
  if (r == VK_TIMEOUT) return Status::Internal("the device did not finish within 120 s");
  if (r != VK_SUCCESS) return VkFailure("vkWaitForFences", r);
  if (timed) {
    std::uint64_t stamps[2] = {0, 0};
    DERMIS_VK(vkGetQueryPoolResults(device_, query_pool_, 0, 2, sizeof(stamps), stamps,
                                    sizeof(std::uint64_t),
                                    VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    const std::uint64_t ticks = (stamps[1] - stamps[0]) & timestamp_mask_;
    *device_seconds = static_cast<double>(ticks) * timestamp_period_ns_ * 1e-9;
  }
  return Status::Ok();
}

int Context::FindMemoryType(std::uint32_t type_bits, VkMemoryPropertyFlags required,
                            VkMemoryPropertyFlags preferred) const {
  int fallback = -1;
  for (std::uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
    if (!(type_bits & (1u << i))) continue;
    const VkMemoryPropertyFlags f = memory_.memoryTypes[i].propertyFlags;
    if ((f & required) != required) continue;
    if ((f & preferred) == preferred) return static_cast<int>(i);
    if (fallback < 0) fallback = static_cast<int>(i);
  }
  return fallback;
}

}  // namespace gpu
}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief dermis::gpu: a small Vulkan host for the GPU evaluation shader (docs/gpu.md). It is a
/// reference for engines, which usually dispatch the shader with their own device, queue and
/// memory from docs/gpu.md alone, and it serves the tests, the benchmark and the samples.
///
/// The model follows the CPU runtime (docs/engine-integration.md): an Output uploads a
/// RuntimeOutput's plan once (device-local, immutable); a Patches ring holds the pose's packed
/// patches, written by the CPU per frame (PoseJob, then Patches::Write); an Evaluation binds
/// both to the engine's vertex buffers and records the dispatches into any command buffer.
/// ReadbackEvaluator does all of it on the context's own queue and reads the vertices back.
///
/// Vulkan loader only (no window, no surface, Vulkan 1.0). No exceptions: every call that can
/// fail returns a Status naming the Vulkan call and its result. Objects made from a Context
/// keep a pointer to it and must be destroyed before it. A Context's own queue (Submit) is used
/// by one thread at a time; recording into the engine's command buffers follows Vulkan's rules.
#pragma once

#include <vulkan/vulkan_core.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/gpu/shader_interface.h"
#include "dermis/runtime/evaluation_plan.h"
#include "dermis/runtime/runtime.h"

namespace dermis {
namespace gpu {

/// Settings of Context::Create().
struct ContextOptions {
  /// Index into vkEnumeratePhysicalDevices(); -1 picks the first device of the best type
  /// (discrete, integrated, virtual, CPU, other) that has a compute queue.
  int device_index = -1;
  /// Enables VK_LAYER_KHRONOS_validation (Debian `vulkan-validationlayers`) when it is
  /// installed, and counts its warnings and errors (validation_messages()).
  bool validation = false;
  /// Optional: called with each validation warning or error and `validation_user`, from any
  /// thread, also while the context is destroyed (where the layer reports objects never
  /// destroyed).
  void (*validation_callback)(const char* message, void* user) = nullptr;
  void* validation_user = nullptr;
};

/// A Vulkan instance, device and compute queue, and the evaluation pipeline.
class Context {
 public:
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  /// Creates the instance, picks a device (ContextOptions), creates it with one compute queue,
  /// and builds the compute pipeline of evaluate_plan.comp. StatusCode::kUnsupported when the
  /// machine has no Vulkan loader, driver or device with a compute queue (the message says
  /// which).
  static Status Create(const ContextOptions& options, std::unique_ptr<Context>* out);

  /// "llvmpipe (LLVM 15.0.6, 256 bits)", the device's own name.
  const std::string& device_name() const { return device_name_; }
  /// "cpu", "discrete GPU", "integrated GPU", "virtual GPU" or "other".
  const char* device_type() const;
  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical_device() const { return physical_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  std::uint32_t queue_family() const { return queue_family_; }
  const VkPhysicalDeviceLimits& limits() const { return limits_; }

  VkDescriptorSetLayout set_layout() const { return set_layout_; }
  VkPipelineLayout pipeline_layout() const { return pipeline_layout_; }
  VkPipeline pipeline() const { return pipeline_; }
  std::uint32_t workgroup_size() const { return workgroup_size_; }

  /// Whether the validation layer is active, and the warnings and errors it reported so far
  /// (the last one's text in last_validation_message()).
  bool validation_enabled() const { return messenger_ != VK_NULL_HANDLE; }
  std::size_t validation_messages() const { return validation_messages_; }
  const std::string& last_validation_message() const { return last_validation_message_; }

  /// Whether Submit() can time the device work (timestamps on the queue).
  bool has_timestamps() const { return timestamp_period_ns_ > 0.0; }

  /// Records `record(cmd)` into the context's command buffer, submits it to the queue and
  /// waits. With `device_seconds`, also measures the device time of the recorded commands by
  /// timestamps (-1 when has_timestamps() is false). Not for concurrent use; no allocation.
  template <class Record>
  Status Submit(Record&& record, double* device_seconds = nullptr) {
    using R = std::remove_reference_t<Record>;
    return SubmitRecorded([](VkCommandBuffer cmd, void* user) { (*static_cast<R*>(user))(cmd); },
                          const_cast<void*>(static_cast<const void*>(&record)), device_seconds);
  }
  /// The same with a plain callback and its argument.
  Status SubmitRecorded(void (*record)(VkCommandBuffer, void*), void* user, double* device_seconds);

  /// Index of a memory type with the `required` property flags among `type_bits`, preferring
  /// one that also has `preferred`; -1 if none.
  int FindMemoryType(std::uint32_t type_bits, VkMemoryPropertyFlags required,
                     VkMemoryPropertyFlags preferred) const;

 private:
  Context() = default;
  static VKAPI_ATTR VkBool32 VKAPI_CALL OnValidation(
      VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
      const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);
  Status CreatePipeline();

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  std::uint32_t queue_family_ = 0;
  VkPhysicalDeviceLimits limits_{};
  VkPhysicalDeviceType device_type_ = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  VkPhysicalDeviceMemoryProperties memory_{};
  std::string device_name_;
  double timestamp_period_ns_ = 0.0;
  std::uint64_t timestamp_mask_ = 0;
  VkCommandPool command_pool_ = VK_NULL_HANDLE;
  VkCommandBuffer command_buffer_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkQueryPool query_pool_ = VK_NULL_HANDLE;
  VkShaderModule shader_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout pipeline_layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  std::uint32_t workgroup_size_ = kDefaultWorkgroupSize;
  std::size_t validation_messages_ = 0;
  std::string last_validation_message_;
  void (*validation_callback_)(const char*, void*) = nullptr;
  void* validation_user_ = nullptr;
};

/// Where a buffer's memory lives.
enum class MemoryUse : std::uint8_t {
  kDevice = 0,    ///< Device-local (may not be mappable).
  kUpload = 1,    ///< Host-visible and coherent, written by the CPU (device-local if possible).
  kReadback = 2,  ///< Host-visible and coherent, read by the CPU (host-cached if possible).
};

/// A VkBuffer with its own memory allocation (persistently mapped unless kDevice).
class Buffer {
 public:
  ~Buffer();
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  /// A buffer of `size` > 0 bytes for `usage`.
  static Status Create(Context& context, VkDeviceSize size, VkBufferUsageFlags usage,
                       MemoryUse memory, std::unique_ptr<Buffer>* out);
  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  /// The mapped bytes, or null for a kDevice buffer.
  void* mapped() const { return mapped_; }

 private:
  Buffer() = default;
  Context* context_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
};

/// Options of Output::Upload().
struct OutputOptions {
  /// Most blocks one descriptor set binds (0: as many as the device's maxStorageBufferRange
  /// allows). Rounded down to the alignment granule; for tests of the chunking.
  std::size_t max_chunk_blocks = 0;
};

/// An EvaluationPlan in device-local memory (bindings 0 and 1), uploaded once through a
/// staging buffer. Immutable; shareable between Evaluations.
class Output {
 public:
  /// A contiguous range of blocks bound by one descriptor set: the plan's data of more blocks
  /// than maxStorageBufferRange covers is split into several ranges (docs/gpu.md).
  struct Chunk {
    std::size_t block_begin = 0;
    std::size_t block_end = 0;
  };

  ~Output();
  Output(const Output&) = delete;
  Output& operator=(const Output&) = delete;
  /// Uploads `output.plan()`; the plan is not referenced afterwards.
  static Status Upload(Context& context, const RuntimeOutput& output, const OutputOptions& options,
                       std::unique_ptr<Output>* out);
  /// The same for any plan.
  static Status Upload(Context& context, const EvaluationPlan& plan, const OutputOptions& options,
                       std::unique_ptr<Output>* out);

  std::size_t num_vertices() const { return num_vertices_; }
  std::size_t num_blocks() const { return num_blocks_; }
  /// Control vertices of the surface: the packed patches an evaluation reads.
  std::size_t num_control_vertices() const { return num_control_vertices_; }
  const std::vector<Chunk>& chunks() const { return chunks_; }
  VkBuffer blocks_buffer() const { return blocks_->handle(); }
  VkBuffer data_buffer() const { return data_->handle(); }
  /// Device bytes of both buffers.
  std::size_t memory_bytes() const;

 private:
  Output() = default;
  std::size_t num_vertices_ = 0, num_blocks_ = 0, num_control_vertices_ = 0;
  std::vector<Chunk> chunks_;
  std::unique_ptr<Buffer> blocks_, data_;
};

/// The pose's packed patches (binding 2) in host-visible memory, `slots` copies so that the
/// CPU writes frame f + 1's while the GPU still reads frame f's (one slot per frame in flight).
class Patches {
 public:
  ~Patches();
  Patches(const Patches&) = delete;
  Patches& operator=(const Patches&) = delete;
  static Status Create(Context& context, std::size_t num_control_vertices, std::uint32_t slots,
                       std::unique_ptr<Patches>* out);
  /// Copies num_control_vertices() * kPackedPatchStride floats into slot `slot`. The slot
  /// must not be in use by the device. Returns false (copying nothing) on a bad slot or null.
  bool Write(std::uint32_t slot, const float* packed);
  /// Copies part `part`'s current packed patches of `instance` (after its PoseJob).
  bool Write(std::uint32_t slot, const RuntimeInstance& instance, std::size_t part);

  std::size_t num_control_vertices() const { return num_control_vertices_; }
  std::uint32_t slots() const { return slots_; }
  VkBuffer buffer() const { return buffer_->handle(); }
  /// Byte offset of a slot in buffer() (aligned to minStorageBufferOffsetAlignment).
  VkDeviceSize slot_offset(std::uint32_t slot) const { return slot * slot_stride_; }
  /// Bytes a slot's patches take (what moves to the device per frame).
  VkDeviceSize slot_bytes() const { return num_control_vertices_ * kPackedPatchBytes; }

 private:
  Patches() = default;
  std::size_t num_control_vertices_ = 0;
  std::uint32_t slots_ = 0;
  VkDeviceSize slot_stride_ = 0;
  std::unique_ptr<Buffer> buffer_;
};

/// One attribute stream of the engine's vertex buffer: vertex i's 3 floats start at
/// `offset + i * stride` bytes of `buffer` (offset and stride multiples of 4, stride >= 12).
struct Stream {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceSize offset = 0;
  std::uint32_t stride = 3 * sizeof(float);
};

/// Where an Evaluation writes: positions, and normals unless normals.buffer is null. The
/// buffers need VK_BUFFER_USAGE_STORAGE_BUFFER_BIT (and VERTEX_BUFFER_BIT to be drawn).
struct Targets {
  Stream positions;
  Stream normals;
};

/// The descriptor sets that bind an Output, a Patches ring and the target streams (one set per
/// chunk and slot), and the recording of the dispatches. Keeps pointers to the Output and the
/// Patches, which must outlive it.
class Evaluation {
 public:
  ~Evaluation();
  Evaluation(const Evaluation&) = delete;
  Evaluation& operator=(const Evaluation&) = delete;
  /// Fails on mismatched control-vertex counts, bad offsets or strides, or streams that do not
  /// fit maxStorageBufferRange.
  static Status Create(Context& context, const Output& output, const Patches& patches,
                       const Targets& targets, std::unique_ptr<Evaluation>* out);

  /// Records the evaluation of every output vertex with patch slot `slot` into `cmd`, a command
  /// buffer in the recording state of a queue family with compute: binds the pipeline, then
  /// per chunk its descriptor set, the push constants and vkCmdDispatch (split where a chunk
  /// needs more workgroups than maxComputeWorkGroupCount[0]). Records no barrier: before the
  /// vertices are drawn or copied, record one (RecordComputeToVertexBarrier()).
  /// Returns false (recording nothing) on a bad slot.
  bool Record(VkCommandBuffer cmd, std::uint32_t slot) const;
  /// vkCmdDispatch calls one Record() makes.
  std::size_t dispatch_count() const;

 private:
  Evaluation() = default;
  struct Dispatch {
    std::size_t chunk;
    PushConstants push;
    std::uint32_t groups;
  };
  Context* context_ = nullptr;
  std::uint32_t slots_ = 0;
  std::size_t num_chunks_ = 0;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  std::vector<VkDescriptorSet> sets_;  // [slot * chunks + chunk]
  std::vector<Dispatch> dispatches_;
};

/// Records the barrier between the shader's writes and the vertex input stage reading the
/// target buffers as vertex attributes (docs/gpu.md, synchronisation).
void RecordComputeToVertexBarrier(VkCommandBuffer cmd);
/// Records the barrier between the shader's writes and transfer reads (a copy of the vertices).
void RecordComputeToTransferBarrier(VkCommandBuffer cmd);

/// Everything for one output on the context's own queue: the uploaded plan, one patch slot, a
/// device-local vertex buffer (position + normal, 24 bytes per vertex) and a readback buffer.
/// Run() evaluates and copies the vertices to host memory; for tests, tools and samples.
class ReadbackEvaluator {
 public:
  ~ReadbackEvaluator();
  static Status Create(Context& context, const RuntimeOutput& output, const OutputOptions& options,
                       std::unique_ptr<ReadbackEvaluator>* out);
  /// Writes `instance`'s current packed patches of the output's part, evaluates on the device,
  /// waits, and scatters positions and normals (normals may be null) into `out` as
  /// EvaluatePlan() does. With `device_seconds`, the device time of the dispatches alone.
  Status Run(const RuntimeInstance& instance, const PlanOutputBuffers& out,
             double* device_seconds = nullptr);
  /// The same from packed patches (num_control_vertices() * kPackedPatchStride floats).
  Status Run(const float* packed_patches, const PlanOutputBuffers& out,
             double* device_seconds = nullptr);
  /// Only the dispatches (no readback); with `device_seconds` as in Run().
  Status Dispatch(const float* packed_patches, double* device_seconds = nullptr);

  const Output& output() const { return *output_; }
  std::size_t num_vertices() const { return output_->num_vertices(); }
  std::size_t num_control_vertices() const { return output_->num_control_vertices(); }

 private:
  ReadbackEvaluator() = default;
  Context* context_ = nullptr;
  std::size_t part_ = 0;
  const RuntimeCharacter* character_ = nullptr;
  std::unique_ptr<Output> output_;
  std::unique_ptr<Patches> patches_;
  std::unique_ptr<Buffer> vertices_, readback_;
  std::unique_ptr<Evaluation> evaluation_;
};

}  // namespace gpu
}  // namespace dermis

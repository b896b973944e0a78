// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Device memory of dermis::gpu (docs/gpu.md, "Buffers"): buffers with their own allocation, the
// upload of an EvaluationPlan (bindings 0 and 1) through a staging buffer and its split into
// chunks that fit maxStorageBufferRange, and the per-frame ring of packed patches (binding 2).
#include <algorithm>
#include <cstring>
#include <numeric>

#include "dermis/gpu/gpu.h"
#include "gpu/vk_result.h"

namespace dermis {
namespace gpu {

namespace {

VkDeviceSize AlignUp(VkDeviceSize x, VkDeviceSize a) { return (x + a - 1) / a * a; }

// Blocks whose start keeps both plan buffers' descriptor offsets aligned.
std::size_t ChunkGranule(VkDeviceSize alignment) {
  const std::size_t a = static_cast<std::size_t>(std::max<VkDeviceSize>(alignment, 1));
  const std::size_t g1 = a / std::gcd(a, kPlanBlockBytes);
  const std::size_t g2 = a / std::gcd(a, kPlanBlockDataBytes);
  return std::lcm(g1, g2);
}

}  // namespace

Buffer::~Buffer() {
  if (!context_) return;
  VkDevice d = context_->device();
  if (mapped_) vkUnmapMemory(d, memory_);
  if (buffer_) vkDestroyBuffer(d, buffer_, nullptr);
  if (memory_) vkFreeMemory(d, memory_, nullptr);
}

Status Buffer::Create(Context& context, VkDeviceSize size, VkBufferUsageFlags usage,
                      MemoryUse memory, std::unique_ptr<Buffer>* out) {
  if (size == 0) return Status::InvalidInput("gpu::Buffer: size 0");
  std::unique_ptr<Buffer> b(new Buffer());
  b->context_ = &context;
  b->size_ = size;
  VkBufferCreateInfo bi{};
  bi.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  bi.size = size;
  bi.usage = usage;
  bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  DERMIS_VK(vkCreateBuffer(context.device(), &bi, nullptr, &b->buffer_));
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(context.device(), b->buffer_, &req);
  const VkMemoryPropertyFlags host =
      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  int type = -1;
  switch (memory) {
    case MemoryUse::kDevice:
      type = context.FindMemoryType(req.memoryTypeBits, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
      break;
    case MemoryUse::kUpload:
      type = context.FindMemoryType(req.memoryTypeBits, host, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
      break;
    case MemoryUse::kReadback:
      type = context.FindMemoryType(req.memoryTypeBits, host, VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
      break;
  }
  if (type < 0) return Status::Unsupported("gpu::Buffer: no suitable memory type on the device");
  VkMemoryAllocateInfo ai{};
  ai.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = static_cast<std::uint32_t>(type);
  DERMIS_VK(vkAllocateMemory(context.device(), &ai, nullptr, &b->memory_));
  DERMIS_VK(vkBindBufferMemory(context.device(), b->buffer_, b->memory_, 0));
  if (memory != MemoryUse::kDevice) {
    DERMIS_VK(vkMapMemory(context.device(), b->memory_, 0, VK_WHOLE_SIZE, 0, &b->mapped_));
  }
  *out = std::move(b);
  return Status::Ok();
}

Output::~Output() = default;

std::size_t Output::memory_bytes() const {
  return static_cast<std::size_t>(blocks_->size() + data_->size());
}

Status Output::Upload(Context& context, const RuntimeOutput& output, const OutputOptions& options,
                      std::unique_ptr<Output>* out) {
  return Upload(context, output.plan(), options, out);
}

Status Output::Upload(Context& context, const EvaluationPlan& plan, const OutputOptions& options,
                      std::unique_ptr<Output>* out) {
  if (!out) return Status::InvalidInput("gpu::Output::Upload: no output");
  std::unique_ptr<Output> o(new Output());
  o->num_vertices_ = plan.num_samples();
  o->num_blocks_ = plan.num_blocks();
  o->num_control_vertices_ = plan.num_vertices();
  const VkDeviceSize block_bytes = o->num_blocks_ * kPlanBlockBytes;
  const VkDeviceSize data_bytes = o->num_blocks_ * kPlanBlockDataBytes;
  if (data_bytes / kPlanBlockDataBytes != o->num_blocks_) {
    return Status::Unsupported("gpu::Output: the plan is too large");
  }

  // Chunks: each binds at most maxStorageBufferRange bytes of either buffer, at offsets
  // aligned to minStorageBufferOffsetAlignment.
  const VkPhysicalDeviceLimits& limits = context.limits();
  const std::size_t granule = ChunkGranule(limits.minStorageBufferOffsetAlignment);
  std::size_t per_chunk = limits.maxStorageBufferRange / kPlanBlockDataBytes;
  if (options.max_chunk_blocks > 0) per_chunk = std::min(per_chunk, options.max_chunk_blocks);
  per_chunk = std::max(granule, per_chunk / granule * granule);
  if (per_chunk * kPlanBlockDataBytes > limits.maxStorageBufferRange) {
    return Status::Unsupported("gpu::Output: the device's maxStorageBufferRange (" +
                               std::to_string(limits.maxStorageBufferRange) +
                               " bytes) is too small for one aligned chunk of plan blocks");
  }
  for (std::size_t b = 0; b < o->num_blocks_; b += per_chunk) {
    o->chunks_.push_back(Chunk{b, std::min(o->num_blocks_, b + per_chunk)});
  }

  const VkBufferUsageFlags usage =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  Status s = Buffer::Create(context, std::max<VkDeviceSize>(block_bytes, 4), usage,
                            MemoryUse::kDevice, &o->blocks_);
  if (!s.ok()) return s.WithContext("gpu::Output: plan blocks");
  s = Buffer::Create(context, std::max<VkDeviceSize>(data_bytes, 4), usage, MemoryUse::kDevice,
                     &o->data_);
  if (!s.ok()) return s.WithContext("gpu::Output: plan data");
  if (o->num_blocks_ > 0) {
    std::unique_ptr<Buffer> staging;
    s = Buffer::Create(context, block_bytes + data_bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                       MemoryUse::kUpload, &staging);
    if (!s.ok()) return s.WithContext("gpu::Output: staging");
    unsigned char* bytes = static_cast<unsigned char*>(staging->mapped());
    std::memcpy(bytes, plan.blocks(), static_cast<std::size_t>(block_bytes));
    std::memcpy(bytes + block_bytes, plan.block_data(), static_cast<std::size_t>(data_bytes));
    const VkBuffer src = staging->handle(), blocks = o->blocks_->handle(),
                   data = o->data_->handle();
    s = context.Submit([&](VkCommandBuffer cmd) {
      VkBufferCopy c{0, 0, block_bytes};
      vkCmdCopyBuffer(cmd, src, blocks, 1, &c);
      c = VkBufferCopy{block_bytes, 0, data_bytes};
      vkCmdCopyBuffer(cmd, src, data, 1, &c);
      // The copies before any later shader read on this queue.
      VkMemoryBarrier mb{};
      mb.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
      mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
      mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
      vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                           VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &mb, 0, nullptr, 0, nullptr);
    });
    if (!s.ok()) return s.WithContext("gpu::Output: upload");
  }
  *out = std::move(o);
  return Status::Ok();
}

Patches::~Patches() = default;

Status Patches::Create(Context& context, std::size_t num_control_vertices, std::uint32_t slots,
                       std::unique_ptr<Patches>* out) {
  if (!out) return Status::InvalidInput("gpu::Patches::Create: no output");
  if (num_control_vertices == 0 || slots == 0) {
    return Status::InvalidInput("gpu::Patches: needs control vertices and at least one slot");
  }
  std::unique_ptr<Patches> p(new Patches());
  p->num_control_vertices_ = num_control_vertices;
  p->slots_ = slots;
  p->slot_stride_ =
      AlignUp(num_control_vertices * kPackedPatchBytes,
              std::max<VkDeviceSize>(1, context.limits().minStorageBufferOffsetAlignment));
  if (p->slot_bytes() > context.limits().maxStorageBufferRange) {
    return Status::Unsupported("gpu::Patches: " + std::to_string(num_control_vertices) +
                               " control vertices exceed the device's maxStorageBufferRange");
  }
  const Status s =
      Buffer::Create(context, p->slot_stride_ * slots, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                     MemoryUse::kUpload, &p->buffer_);
  if (!s.ok()) return s.WithContext("gpu::Patches");
  std::memset(p->buffer_->mapped(), 0, static_cast<std::size_t>(p->buffer_->size()));
  *out = std::move(p);
  return Status::Ok();
}

bool Patches::Write(std::uint32_t slot, const float* packed) {
  if (slot >= slots_ || !packed) return false;
  // Host-coherent memory: the next vkQueueSubmit makes the write visible to the device.
  std::memcpy(static_cast<unsigned char*>(buffer_->mapped()) + slot_offset(slot), packed,
              static_cast<std::size_t>(slot_bytes()));
  return true;
}

bool Patches::Write(std::uint32_t slot, const RuntimeInstance& instance, std::size_t part) {
  if (part >= instance.character().num_parts() ||
      instance.character().num_control_vertices(part) != num_control_vertices_) {
    return false;
  }
  return Write(slot, instance.packed_patches(part));
}

}  // namespace gpu
}  // namespace dermis

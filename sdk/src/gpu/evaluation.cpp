// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Recording the GPU evaluation (docs/gpu.md, "Dispatch" and "Synchronisation"): descriptor sets
// per (patch slot, plan chunk), push constants and workgroup counts per dispatch, the barriers
// an engine needs, and the readback evaluator the tests, the benchmark and the samples use.
#include <algorithm>
#include <cstring>

#include "dermis/gpu/gpu.h"
#include "gpu/vk_result.h"

namespace dermis {
namespace gpu {

namespace {

// A stream split into the descriptor's aligned offset and range and the shader's byte offset.
struct BoundStream {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceSize bind_offset = 0;
  VkDeviceSize range = 0;
  std::uint32_t offset = 0;
  std::uint32_t stride = 0;
};

Status BindStream(const Context& context, const Stream& s, std::size_t vertices, const char* what,
                  BoundStream* out) {
  const std::string name = std::string("gpu::Evaluation: ") + what;
  if (s.buffer == VK_NULL_HANDLE) return Status::InvalidInput(name + " buffer is null");
  if (s.offset % 4 != 0 || s.stride % 4 != 0 || s.stride < 3 * sizeof(float)) {
    return Status::InvalidInput(name + " offset " + std::to_string(s.offset) + " and stride " +
                                std::to_string(s.stride) +
                                " must be multiples of 4, the stride at least 12");
  }
  const VkDeviceSize align =
      std::max<VkDeviceSize>(4, context.limits().minStorageBufferOffsetAlignment);
  out->buffer = s.buffer;
  out->bind_offset = s.offset / align * align;
  out->offset = static_cast<std::uint32_t>(s.offset - out->bind_offset);
  out->stride = s.stride;
  const VkDeviceSize last = vertices > 0 ? (vertices - 1) : 0;
  out->range = out->offset + last * s.stride + 3 * sizeof(float);
  if (out->range > context.limits().maxStorageBufferRange) {
    return Status::Unsupported(name + " stream spans " + std::to_string(out->range) +
                               " bytes, more than the device's maxStorageBufferRange (" +
                               std::to_string(context.limits().maxStorageBufferRange) + ")");
  }
  return Status::Ok();
}

void ExecutionBarrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags src_access,
                      VkPipelineStageFlags dst, VkAccessFlags dst_access) {
  VkMemoryBarrier mb{};
  mb.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  mb.srcAccessMask = src_access;
  mb.dstAccessMask = dst_access;
  vkCmdPipelineBarrier(cmd, src, dst, 0, 1, &mb, 0, nullptr, 0, nullptr);
}

}  // namespace

Evaluation::~Evaluation() {
  if (context_ && pool_) vkDestroyDescriptorPool(context_->device(), pool_, nullptr);
}

Status Evaluation::Create(Context& context, const Output& output, const Patches& patches,
                          const Targets& targets, std::unique_ptr<Evaluation>* out) {
  if (!out) return Status::InvalidInput("gpu::Evaluation::Create: no output");
  if (output.num_control_vertices() != patches.num_control_vertices()) {
    return Status::InvalidInput("gpu::Evaluation: the output's surface has " +
                                std::to_string(output.num_control_vertices()) +
                                " control vertices, the patches " +
                                std::to_string(patches.num_control_vertices()));
  }
  BoundStream pos, nrm;
  Status s = BindStream(context, targets.positions, output.num_vertices(), "positions", &pos);
  if (!s.ok()) return s;
  const bool normals = targets.normals.buffer != VK_NULL_HANDLE;
  if (normals) {
    s = BindStream(context, targets.normals, output.num_vertices(), "normals", &nrm);
    if (!s.ok()) return s;
  } else {
    nrm = pos;  // a valid descriptor the shader does not write (normal_stride 0)
  }

  std::unique_ptr<Evaluation> e(new Evaluation());
  e->context_ = &context;
  e->slots_ = patches.slots();
  e->num_chunks_ = output.chunks().size();
  const std::size_t sets = e->slots_ * e->num_chunks_;
  if (sets > 0) {
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                              static_cast<std::uint32_t>(sets * kBindingCount)};
    VkDescriptorPoolCreateInfo pi{};
    pi.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
    pi.maxSets = static_cast<std::uint32_t>(sets);
    pi.poolSizeCount = 1;
    pi.pPoolSizes = &size;
    DERMIS_VK(vkCreateDescriptorPool(context.device(), &pi, nullptr, &e->pool_));
    std::vector<VkDescriptorSetLayout> layouts(sets, context.set_layout());
    e->sets_.resize(sets);
    VkDescriptorSetAllocateInfo ai{};
    ai.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
    ai.descriptorPool = e->pool_;
    ai.descriptorSetCount = static_cast<std::uint32_t>(sets);
    ai.pSetLayouts = layouts.data();
    DERMIS_VK(vkAllocateDescriptorSets(context.device(), &ai, e->sets_.data()));
  }
  for (std::uint32_t slot = 0; slot < e->slots_; ++slot) {
    for (std::size_t c = 0; c < e->num_chunks_; ++c) {
      const Output::Chunk& chunk = output.chunks()[c];
      const VkDeviceSize nb = chunk.block_end - chunk.block_begin;
      const VkDescriptorBufferInfo infos[kBindingCount] = {
          {output.blocks_buffer(), chunk.block_begin * kPlanBlockBytes, nb * kPlanBlockBytes},
          {output.data_buffer(), chunk.block_begin * kPlanBlockDataBytes, nb * kPlanBlockDataBytes},
          {patches.buffer(), patches.slot_offset(slot), patches.slot_bytes()},
          {pos.buffer, pos.bind_offset, pos.range},
          {nrm.buffer, nrm.bind_offset, nrm.range}};
      VkWriteDescriptorSet writes[kBindingCount];
      for (std::uint32_t b = 0; b < kBindingCount; ++b) {
        writes[b] = VkWriteDescriptorSet{};
        writes[b].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
        writes[b].dstSet = e->sets_[slot * e->num_chunks_ + c];
        writes[b].dstBinding = b;
        writes[b].descriptorCount = 1;
        writes[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        writes[b].pBufferInfo = &infos[b];
      }
      vkUpdateDescriptorSets(context.device(), kBindingCount, writes, 0, nullptr);
    }
  }
  // Dispatches: per chunk, as many as maxComputeWorkGroupCount[0] requires.
  const std::uint32_t wg = context.workgroup_size();
  const std::size_t max_blocks = std::max<std::size_t>(
      1, static_cast<std::size_t>(context.limits().maxComputeWorkGroupCount[0]) * wg / kPlanLanes);
  for (std::size_t c = 0; c < e->num_chunks_; ++c) {
    const Output::Chunk& chunk = output.chunks()[c];
    const std::size_t nb = chunk.block_end - chunk.block_begin;
    for (std::size_t b = 0; b < nb; b += max_blocks) {
      Dispatch d;
      d.chunk = c;
      d.push.block_begin = static_cast<std::uint32_t>(b);
      d.push.block_end = static_cast<std::uint32_t>(std::min(nb, b + max_blocks));
      d.push.position_offset = pos.offset;
      d.push.position_stride = pos.stride;
      d.push.normal_offset = normals ? nrm.offset : 0u;
      d.push.normal_stride = normals ? nrm.stride : 0u;
      d.groups = static_cast<std::uint32_t>(WorkgroupCount(d.push.block_end - b, wg));
      e->dispatches_.push_back(d);
    }
  }
  *out = std::move(e);
  return Status::Ok();
}

std::size_t Evaluation::dispatch_count() const { return dispatches_.size(); }

bool Evaluation::Record(VkCommandBuffer cmd, std::uint32_t slot) const {
  if (slot >= slots_ || cmd == VK_NULL_HANDLE) return false;
  if (dispatches_.empty()) return true;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, context_->pipeline());
  for (const Dispatch& d : dispatches_) {
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, context_->pipeline_layout(), 0, 1,
                            &sets_[slot * num_chunks_ + d.chunk], 0, nullptr);
    vkCmdPushConstants(cmd, context_->pipeline_layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0,
                       sizeof(PushConstants), &d.push);
    vkCmdDispatch(cmd, d.groups, 1, 1);
  }
  return true;
}

void RecordComputeToVertexBarrier(VkCommandBuffer cmd) {
  ExecutionBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                   VK_PIPELINE_STAGE_VERTEX_INPUT_BIT, VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT);
}

void RecordComputeToTransferBarrier(VkCommandBuffer cmd) {
  ExecutionBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                   VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
}

ReadbackEvaluator::~ReadbackEvaluator() = default;

Status ReadbackEvaluator::Create(Context& context, const RuntimeOutput& output,
                                 const OutputOptions& options,
                                 std::unique_ptr<ReadbackEvaluator>* out) {
  if (!out) return Status::InvalidInput("gpu::ReadbackEvaluator::Create: no output");
  std::unique_ptr<ReadbackEvaluator> r(new ReadbackEvaluator());
  r->context_ = &context;
  r->part_ = output.part();
  r->character_ = &output.character();
  Status s = Output::Upload(context, output, options, &r->output_);
  if (!s.ok()) return s;
  s = Patches::Create(context, r->output_->num_control_vertices(), 1, &r->patches_);
  if (!s.ok()) return s;
  const VkDeviceSize bytes =
      std::max<VkDeviceSize>(1, r->output_->num_vertices()) * 6 * sizeof(float);
  s = Buffer::Create(context, bytes,
                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_VERTEX_BUFFER_BIT |
                         VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                     MemoryUse::kDevice, &r->vertices_);
  if (!s.ok()) return s.WithContext("gpu::ReadbackEvaluator: vertices");
  s = Buffer::Create(context, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::kReadback,
                     &r->readback_);
  if (!s.ok()) return s.WithContext("gpu::ReadbackEvaluator: readback");
  Targets t;
  t.positions = Stream{r->vertices_->handle(), 0, 6 * sizeof(float)};
  t.normals = Stream{r->vertices_->handle(), 3 * sizeof(float), 6 * sizeof(float)};
  s = Evaluation::Create(context, *r->output_, *r->patches_, t, &r->evaluation_);
  if (!s.ok()) return s;
  *out = std::move(r);
  return Status::Ok();
}

Status ReadbackEvaluator::Dispatch(const float* packed_patches, double* device_seconds) {
  if (!packed_patches) return Status::InvalidInput("gpu::ReadbackEvaluator: no patches");
  patches_->Write(0, packed_patches);
  return context_->Submit(
      [&](VkCommandBuffer cmd) {
        // The previous submission's copy read the vertices: finish it before overwriting them.
        ExecutionBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, 0,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0);
        evaluation_->Record(cmd, 0);
      },
      device_seconds);
}

Status ReadbackEvaluator::Run(const RuntimeInstance& instance, const PlanOutputBuffers& out,
                              double* device_seconds) {
  if (&instance.character() != character_) {
    return Status::InvalidInput("gpu::ReadbackEvaluator: the instance is of another character");
  }
  return Run(instance.packed_patches(part_), out, device_seconds);
}

Status ReadbackEvaluator::Run(const float* packed_patches, const PlanOutputBuffers& out,
                              double* device_seconds) {
  if (!packed_patches) return Status::InvalidInput("gpu::ReadbackEvaluator: no patches");
  if (!out.positions || out.position_stride < 3 * sizeof(float) ||
      (out.normals && out.normal_stride < 3 * sizeof(float))) {
    return Status::InvalidInput("gpu::ReadbackEvaluator: bad output buffers or strides");
  }
  const std::size_t n = output_->num_vertices();
  patches_->Write(0, packed_patches);
  const VkBuffer src = vertices_->handle(), dst = readback_->handle();
  const VkDeviceSize bytes = std::max<std::size_t>(1, n) * 6 * sizeof(float);
  const Status s = context_->Submit(
      [&](VkCommandBuffer cmd) {
        ExecutionBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, 0,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0);
        evaluation_->Record(cmd, 0);
        RecordComputeToTransferBarrier(cmd);
        const VkBufferCopy c{0, 0, bytes};
        vkCmdCopyBuffer(cmd, src, dst, 1, &c);
        ExecutionBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                         VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
      },
      device_seconds);
  if (!s.ok()) return s;
  const float* v = static_cast<const float*>(readback_->mapped());
  for (std::size_t i = 0; i < n; ++i) {
    std::memcpy(reinterpret_cast<unsigned char*>(out.positions) + i * out.position_stride,
                v + 6 * i, 3 * sizeof(float));
    if (out.normals) {
      std::memcpy(reinterpret_cast<unsigned char*>(out.normals) + i * out.normal_stride,
                  v + 6 * i + 3, 3 * sizeof(float));
    }
  }
  return Status::Ok();
}

}  // namespace gpu
}  // namespace dermis

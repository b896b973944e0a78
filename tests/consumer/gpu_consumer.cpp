// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Uses dermis::gpu from the installed package (find_package(dermis) brings in Vulkan): the
// embedded SPIR-V is there, and on a machine with a Vulkan device the plan of a built-in
// surface evaluates on it like on the CPU. Prints "gpu consumer ok" (or "... no device") and
// exits 0 when everything worked.
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "dermis/gpu/gpu.h"
#include "dermis/offline/build/domain_builder.h"
#include "dermis/offline/geometry/builtin_meshes.h"

int main() {
  std::size_t words = 0;
  const std::uint32_t* spirv = dermis::gpu::EvaluateShaderSpirv(&words);
  if (words < 100 || spirv[0] != 0x07230203u) return 1;
  std::unique_ptr<dermis::gpu::Context> context;
  const dermis::Status s = dermis::gpu::Context::Create({}, &context);
  if (!s.ok()) {
    std::printf("gpu consumer ok, no device: %s\n", s.message().c_str());
    return s.code() == dermis::StatusCode::kUnsupported ? 0 : 1;
  }
  dermis::PolygonMesh mesh;
  if (!dermis::MakeBuiltinMesh("torus", &mesh).ok()) return 1;
  dermis::ControlSurface surface;
  if (!dermis::BuildControlSurface(mesh, dermis::DomainOptions{}, &surface).ok()) return 1;
  dermis::TessellationPattern pattern;
  if (!dermis::TessellationPattern::Build(surface.domain->topology(), 4, &pattern).ok()) return 1;
  dermis::EvaluationPlan plan;
  if (!dermis::EvaluationPlan::Build(*surface.domain, nullptr, pattern.samples.data(),
                                     pattern.samples.size(), {}, &plan)
           .ok()) {
    return 1;
  }
  const std::size_t n = plan.num_samples(), cvs = plan.num_vertices();
  std::vector<float> packed(cvs * dermis::kPackedPatchStride);
  dermis::PackPatches(surface.patches.data(), cvs, packed.data());
  std::unique_ptr<dermis::gpu::Output> output;
  std::unique_ptr<dermis::gpu::Patches> patches;
  std::unique_ptr<dermis::gpu::Buffer> target;
  std::unique_ptr<dermis::gpu::Evaluation> evaluation;
  if (!dermis::gpu::Output::Upload(*context, plan, {}, &output).ok() ||
      !dermis::gpu::Patches::Create(*context, cvs, 1, &patches).ok() ||
      !dermis::gpu::Buffer::Create(*context, n * 24, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                   dermis::gpu::MemoryUse::kReadback, &target)
           .ok()) {
    return 1;
  }
  dermis::gpu::Targets t;
  t.positions = {target->handle(), 0, 24};
  t.normals = {target->handle(), 12, 24};
  if (!dermis::gpu::Evaluation::Create(*context, *output, *patches, t, &evaluation).ok()) return 1;
  patches->Write(0, packed.data());
  if (!context
           ->Submit([&](VkCommandBuffer cmd) {
             evaluation->Record(cmd, 0);
             VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr,
                                VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_HOST_READ_BIT};
             vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                  VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, nullptr, 0, nullptr);
           })
           .ok()) {
    return 1;
  }
  std::vector<float> cpu(6 * n);
  dermis::PlanOutputBuffers b;
  b.positions = cpu.data();
  b.normals = cpu.data() + 3;
  b.position_stride = b.normal_stride = 24;
  if (!dermis::EvaluatePlan(plan, packed.data(), 0, plan.num_blocks(), b)) return 1;
  const float* gpu = static_cast<const float*>(target->mapped());
  double worst = 0.0;
  for (std::size_t i = 0; i < 6 * n; ++i) worst = std::fmax(worst, std::fabs(gpu[i] - cpu[i]));
  if (!(worst < 1e-4)) {
    std::printf("gpu consumer: GPU and CPU differ by %g\n", worst);
    return 1;
  }
  std::printf("gpu consumer ok on %s (%zu vertices, largest difference %g)\n",
              context->device_name().c_str(), n, worst);
  return 0;
}

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The C API of dermis::gpu (dermis/dermis_gpu.h) over gpu::Context and gpu::ReadbackEvaluator.
#include <new>
#include <string>

#include "dermis/dermis_gpu.h"
#include "dermis/gpu/gpu.h"
#include "runtime/c_api_handles.h"

struct dermis_gpu_context {
  std::unique_ptr<dermis::gpu::Context> impl;
};
struct dermis_gpu_output {
  std::unique_ptr<dermis::gpu::ReadbackEvaluator> impl;
};

using dermis::c_api::Fail;
using dermis::c_api::FromStatus;

extern "C" {

dermis_status dermis_gpu_context_create(int32_t device_index, dermis_gpu_context** out) {
  if (!out) return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_gpu_context_create: null argument");
  *out = nullptr;
  dermis::gpu::ContextOptions options;
  options.device_index = device_index;
  std::unique_ptr<dermis::gpu::Context> c;
  const dermis::Status s = dermis::gpu::Context::Create(options, &c);
  if (!s.ok()) {
    if (s.code() == dermis::StatusCode::kInvalidInput) {
      return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_gpu_context_create: " + s.message());
    }
    return FromStatus(s.WithContext("dermis_gpu_context_create"));
  }
  *out = new (std::nothrow) dermis_gpu_context{std::move(c)};
  return *out ? DERMIS_OK : Fail(DERMIS_ERROR_INTERNAL, "out of memory");
}

void dermis_gpu_context_destroy(dermis_gpu_context* context) { delete context; }

const char* dermis_gpu_device_name(const dermis_gpu_context* context) {
  return context ? context->impl->device_name().c_str() : "";
}

dermis_status dermis_gpu_output_create(dermis_gpu_context* context, const dermis_output* output,
                                       dermis_gpu_output** out) {
  if (!context || !output || !out) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_gpu_output_create: null argument");
  }
  *out = nullptr;
  std::unique_ptr<dermis::gpu::ReadbackEvaluator> e;
  const dermis::Status s =
      dermis::gpu::ReadbackEvaluator::Create(*context->impl, *output->impl, {}, &e);
  if (!s.ok()) return FromStatus(s.WithContext("dermis_gpu_output_create"));
  *out = new (std::nothrow) dermis_gpu_output{std::move(e)};
  return *out ? DERMIS_OK : Fail(DERMIS_ERROR_INTERNAL, "out of memory");
}

void dermis_gpu_output_destroy(dermis_gpu_output* output) { delete output; }

dermis_status dermis_gpu_evaluate(dermis_gpu_output* output, const dermis_instance* instance,
                                  float* positions, size_t position_stride, float* normals,
                                  size_t normal_stride) {
  if (!output || !instance) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_gpu_evaluate: null handle");
  }
  dermis::PlanOutputBuffers buffers;
  buffers.positions = positions;
  buffers.position_stride = position_stride;
  buffers.normals = normals;
  buffers.normal_stride = normal_stride;
  const dermis::Status s = output->impl->Run(*instance->impl, buffers);
  if (!s.ok()) {
    if (s.code() == dermis::StatusCode::kInvalidInput) {
      return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_gpu_evaluate: " + s.message());
    }
    return FromStatus(s.WithContext("dermis_gpu_evaluate"));
  }
  return DERMIS_OK;
}

const uint32_t* dermis_gpu_shader_spirv(size_t* word_count) {
  return dermis::gpu::EvaluateShaderSpirv(word_count);
}

}  // extern "C"

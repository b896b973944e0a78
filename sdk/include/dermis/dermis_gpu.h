/* Copyright (c) Dermis authors. SPDX-License-Identifier: MIT */
/** \file
 * \brief The C API of dermis::gpu (docs/gpu.md): the runtime's evaluation on a Vulkan device.
 * A separate header and library (dermis::gpu, -ldermis_gpu -lvulkan) so that the runtime's C
 * library (dermis/dermis.h) needs no Vulkan. C99; errors as in dermis/dermis.h
 * (dermis_last_error()).
 *
 * This is the reference host: it creates its own Vulkan instance, device and queue, uploads an
 * output's plan once, and per call writes the instance's patches, dispatches the shader, waits
 * and copies the vertices back to host memory (for tools, tests and headless use). An engine
 * that draws the vertices dispatches the shader with its own device instead: docs/gpu.md,
 * dermis_gpu_shader_spirv(), dermis_output_plan() and dermis_instance_packed_patches().
 */
#ifndef DERMIS_DERMIS_GPU_H_
#define DERMIS_DERMIS_GPU_H_

#include <stddef.h>
#include <stdint.h>

#include "dermis/dermis.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dermis_gpu_context dermis_gpu_context;
typedef struct dermis_gpu_output dermis_gpu_output;

/** Creates a Vulkan context on device `device_index` (the order of vkEnumeratePhysicalDevices;
 * -1: the best device with a compute queue, discrete first). DERMIS_ERROR_UNSUPPORTED when the
 * machine has no Vulkan driver or device (the message says which). */
dermis_status dermis_gpu_context_create(int32_t device_index, dermis_gpu_context** out);
void dermis_gpu_context_destroy(dermis_gpu_context* context);
/** The device's name ("" for NULL); owned by the context. */
const char* dermis_gpu_device_name(const dermis_gpu_context* context);

/** Uploads `output`'s plan to the device and allocates its vertex and patch buffers. The
 * output must outlive the GPU output, which must be destroyed before its context. */
dermis_status dermis_gpu_output_create(dermis_gpu_context* context, const dermis_output* output,
                                       dermis_gpu_output** out);
void dermis_gpu_output_destroy(dermis_gpu_output* output);

/** Evaluates the whole output on the device with the instance's current pose (after
 * dermis_instance_pose()), waits, and writes vertex i's position (3 floats) at positions + i *
 * position_stride bytes and its unit normal at normals + i * normal_stride (normals may be
 * NULL), as dermis_evaluate() does. Uses the context's queue: one thread at a time per
 * context. */
dermis_status dermis_gpu_evaluate(dermis_gpu_output* output, const dermis_instance* instance,
                                  float* positions, size_t position_stride, float* normals,
                                  size_t normal_stride);

/** The SPIR-V of the evaluation shader (Vulkan 1.0, entry point "main"): `*word_count` 32-bit
 * words, static storage. Its interface: docs/gpu.md. */
const uint32_t* dermis_gpu_shader_spirv(size_t* word_count);

#ifdef __cplusplus
}
#endif

#endif /* DERMIS_DERMIS_GPU_H_ */

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The C API (dermis/dermis.h) over the C++ runtime (dermis/runtime/runtime.h).
#include <algorithm>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include "dermis/dermis.h"
#include "dermis/runtime/runtime.h"
#include "runtime/c_api_handles.h"

namespace dermis {
namespace c_api {

namespace {
thread_local std::string g_last_error;
}  // namespace

const char* LastError() { return g_last_error.c_str(); }

dermis_status Fail(dermis_status status, const std::string& message) {
  g_last_error = message;
  return status;
}

dermis_status FromStatus(const dermis::Status& s) {
  if (s.ok()) return DERMIS_OK;
  switch (s.code()) {
    case dermis::StatusCode::kInvalidInput:
      return Fail(DERMIS_ERROR_INVALID_INPUT, s.message());
    case dermis::StatusCode::kIoError:
      return Fail(DERMIS_ERROR_IO, s.message());
    case dermis::StatusCode::kUnsupported:
      return Fail(DERMIS_ERROR_UNSUPPORTED, s.message());
    default:
      return Fail(DERMIS_ERROR_INTERNAL, s.message());
  }
}

}  // namespace c_api
}  // namespace dermis

namespace {

using dermis::c_api::Fail;
using dermis::c_api::FromStatus;

bool PartOk(const dermis_character* c, size_t part) { return c && part < c->impl->num_parts(); }

}  // namespace

extern "C" {

// The header's version macros must be the project's (CMake passes its version here).
static_assert(DERMIS_VERSION_MAJOR == DERMIS_PROJECT_VERSION_MAJOR &&
                  DERMIS_VERSION_MINOR == DERMIS_PROJECT_VERSION_MINOR &&
                  DERMIS_VERSION_PATCH == DERMIS_PROJECT_VERSION_PATCH,
              "dermis.h's DERMIS_VERSION_* disagree with the project version in CMakeLists.txt");

const char* dermis_version(void) { return DERMIS_VERSION_STRING; }

uint32_t dermis_version_number(void) { return DERMIS_VERSION_NUMBER; }

const char* dermis_last_error(void) { return dermis::c_api::LastError(); }

const char* dermis_status_string(dermis_status status) {
  switch (status) {
    case DERMIS_OK:
      return "ok";
    case DERMIS_ERROR_INVALID_ARGUMENT:
      return "invalid argument";
    case DERMIS_ERROR_INVALID_INPUT:
      return "invalid input";
    case DERMIS_ERROR_IO:
      return "i/o error";
    case DERMIS_ERROR_UNSUPPORTED:
      return "unsupported";
    case DERMIS_ERROR_INTERNAL:
      return "internal error";
  }
  return "unknown status";
}

dermis_status dermis_character_load(const char* path, dermis_character** out) {
  if (!path || !out)
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_character_load: null argument");
  *out = nullptr;
  std::unique_ptr<dermis::RuntimeCharacter> c;
  const dermis_status s = FromStatus(dermis::RuntimeCharacter::Load(path, &c));
  if (s != DERMIS_OK) return s;
  *out = new (std::nothrow) dermis_character{std::move(c)};
  return *out ? DERMIS_OK : Fail(DERMIS_ERROR_INTERNAL, "out of memory");
}

dermis_status dermis_character_load_memory(const void* bytes, size_t size, const char* name,
                                           dermis_character** out) {
  if ((!bytes && size > 0) || !out) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_character_load_memory: null argument");
  }
  *out = nullptr;
  std::unique_ptr<dermis::RuntimeCharacter> c;
  const std::string_view view(static_cast<const char*>(bytes), size);
  const dermis_status s =
      FromStatus(dermis::RuntimeCharacter::FromBytes(view, name ? name : "memory", &c));
  if (s != DERMIS_OK) return s;
  *out = new (std::nothrow) dermis_character{std::move(c)};
  return *out ? DERMIS_OK : Fail(DERMIS_ERROR_INTERNAL, "out of memory");
}

void dermis_character_destroy(dermis_character* character) { delete character; }

size_t dermis_character_memory_bytes(const dermis_character* c) {
  return c ? sizeof(dermis_character) + c->impl->memory_bytes() : 0;
}

const char* dermis_character_joint_name(const dermis_character* c, size_t part, size_t joint) {
  const dermis::SkinRig* rig = PartOk(c, part) ? c->impl->rig(part) : nullptr;
  if (!rig || joint >= rig->parents.size()) return nullptr;
  return joint < rig->names.size() ? rig->names[joint].c_str() : "";
}

dermis_status dermis_character_joint_remap(const dermis_character* c, size_t part,
                                           const char* const* engine_names,
                                           size_t engine_joint_count, int32_t* remap,
                                           size_t remap_count) {
  if (!PartOk(c, part)) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT,
                "dermis_character_joint_remap: part " + std::to_string(part) + " does not exist");
  }
  const size_t joints = c->impl->num_joints(part);
  if ((engine_joint_count > 0 && !engine_names) || (joints > 0 && !remap)) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_character_joint_remap: null argument");
  }
  if (remap_count < joints) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_character_joint_remap: the remap holds " +
                                                   std::to_string(remap_count) + " entries, part " +
                                                   std::to_string(part) + " has " +
                                                   std::to_string(joints) + " joints");
  }
  std::vector<std::string_view> names(engine_joint_count);
  for (size_t i = 0; i < engine_joint_count; ++i) {
    if (!engine_names[i]) {
      return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_character_joint_remap: engine joint " +
                                                     std::to_string(i) + " has a null name");
    }
    names[i] = engine_names[i];
  }
  std::vector<int32_t> result;
  const dermis_status s = FromStatus(c->impl->RemapJointsByName(part, names, &result));
  if (s != DERMIS_OK) return s;
  std::copy(result.begin(), result.end(), remap);
  return DERMIS_OK;
}

size_t dermis_character_part_count(const dermis_character* c) {
  return c ? c->impl->num_parts() : 0;
}

size_t dermis_character_joint_count(const dermis_character* c, size_t part) {
  return PartOk(c, part) ? c->impl->num_joints(part) : 0;
}

size_t dermis_character_control_vertex_count(const dermis_character* c, size_t part) {
  return PartOk(c, part) ? c->impl->num_control_vertices(part) : 0;
}

int32_t dermis_character_joint_parent(const dermis_character* c, size_t part, size_t joint) {
  const dermis::SkinRig* rig = PartOk(c, part) ? c->impl->rig(part) : nullptr;
  return rig && joint < rig->parents.size() ? rig->parents[joint] : -1;
}

dermis_status dermis_character_joint_bind(const dermis_character* c, size_t part, size_t joint,
                                          float* out) {
  const dermis::SkinRig* rig = PartOk(c, part) ? c->impl->rig(part) : nullptr;
  if (!rig || joint >= rig->bind.size() || !out) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_character_joint_bind: part " +
                                                   std::to_string(part) + " joint " +
                                                   std::to_string(joint) + " out of range");
  }
  for (int col = 0; col < 4; ++col) {
    for (int row = 0; row < 4; ++row)
      out[4 * col + row] = static_cast<float>(rig->bind[joint][col][row]);
  }
  return DERMIS_OK;
}

size_t dermis_character_bound_vertex_count(const dermis_character* c, size_t part) {
  return PartOk(c, part) ? c->impl->bound_vertices(part).size() : 0;
}

dermis_status dermis_character_bound_vertex(const dermis_character* c, size_t part, size_t index,
                                            int32_t* mesh, int32_t* primitive, int32_t* vertex) {
  if (!PartOk(c, part) || index >= c->impl->bound_vertices(part).size()) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_character_bound_vertex: part " +
                                                   std::to_string(part) + " vertex " +
                                                   std::to_string(index) + " out of range");
  }
  const dermis::BoundVertexRef& r = c->impl->bound_vertices(part)[index];
  if (mesh) *mesh = r.mesh;
  if (primitive) *primitive = r.primitive;
  if (vertex) *vertex = r.vertex;
  return DERMIS_OK;
}

void dermis_output_desc_init(dermis_output_desc* desc) {
  if (!desc) return;
  desc->kind = DERMIS_OUTPUT_LEVEL;
  desc->level = 4;
  desc->displacement_levels = -1;
  desc->threads = 1;
  desc->tangents = 0;
}

dermis_status dermis_output_create(const dermis_character* c, size_t part,
                                   const dermis_output_desc* desc, dermis_output** out) {
  if (!c || !desc || !out)
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_output_create: null argument");
  *out = nullptr;
  if (!PartOk(c, part)) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT,
                "dermis_output_create: part " + std::to_string(part) + " does not exist");
  }
  if (desc->kind != DERMIS_OUTPUT_BOUND && desc->kind != DERMIS_OUTPUT_LEVEL) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_output_create: unknown output kind");
  }
  dermis::OutputSpec spec;
  spec.kind =
      desc->kind == DERMIS_OUTPUT_BOUND ? dermis::OutputKind::kBound : dermis::OutputKind::kLevel;
  spec.level = desc->level;
  spec.displacement_levels = desc->displacement_levels;
  spec.threads = desc->threads;
  spec.tangents = desc->tangents != 0;
  std::unique_ptr<dermis::RuntimeOutput> o;
  const dermis::Status s = dermis::RuntimeOutput::Build(*c->impl, part, spec, &o);
  if (!s.ok()) {
    return Fail(s.code() == dermis::StatusCode::kInvalidInput ? DERMIS_ERROR_INVALID_ARGUMENT
                                                              : DERMIS_ERROR_INTERNAL,
                s.message());
  }
  *out = new (std::nothrow) dermis_output{std::move(o)};
  return *out ? DERMIS_OK : Fail(DERMIS_ERROR_INTERNAL, "out of memory");
}

void dermis_output_destroy(dermis_output* output) { delete output; }

size_t dermis_output_memory_bytes(const dermis_output* o) {
  return o ? sizeof(dermis_output) + sizeof(dermis::RuntimeOutput) + o->impl->memory_bytes() : 0;
}

size_t dermis_output_required_bytes(const dermis_output* o, size_t block_begin, size_t block_end,
                                    size_t stride) {
  if (!o) return 0;
  const dermis::EvaluationPlan& plan = o->impl->plan();
  const size_t end = std::min(block_end, plan.num_blocks());
  if (block_begin >= end) return 0;
  // Lanes name their output vertex (blocks group a face's samples, not consecutive
  // vertices): the whole output ends at its last vertex, a sub-range at its largest index.
  size_t last_vertex = plan.num_samples() - 1;
  if (block_begin > 0 || end < plan.num_blocks()) {
    int32_t largest = 0;
    for (size_t b = block_begin; b < end; ++b) {
      const dermis::PlanBlock& block = plan.blocks()[b];
      for (int32_t lane = 0; lane < block.count; ++lane)
        largest = std::max(largest, block.index[lane]);
    }
    last_vertex = static_cast<size_t>(largest);
  }
  return last_vertex * stride + 3 * sizeof(float);
}

size_t dermis_output_vertex_count(const dermis_output* o) {
  return o ? o->impl->num_vertices() : 0;
}

size_t dermis_output_triangle_count(const dermis_output* o) {
  return o ? o->impl->triangles().size() / 3 : 0;
}

const uint32_t* dermis_output_triangles(const dermis_output* o) {
  return o && !o->impl->triangles().empty() ? o->impl->triangles().data() : nullptr;
}

size_t dermis_output_block_count(const dermis_output* o) {
  return o ? o->impl->plan().num_blocks() : 0;
}

dermis_status dermis_instance_create(const dermis_character* c, dermis_deformer deformer,
                                     dermis_instance** out) {
  if (!c || !out)
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_instance_create: null argument");
  *out = nullptr;
  if (static_cast<int>(deformer) < 0 || static_cast<int>(deformer) > 255 ||
      !dermis::FindDeformer(static_cast<dermis::DeformerKind>(deformer))) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_instance_create: unknown deformer");
  }
  std::unique_ptr<dermis::RuntimeInstance> inst;
  const dermis_status s = FromStatus(dermis::RuntimeInstance::Create(
      *c->impl, static_cast<dermis::DeformerKind>(deformer), &inst));
  if (s != DERMIS_OK) return s;
  *out = new (std::nothrow) dermis_instance{std::move(inst)};
  return *out ? DERMIS_OK : Fail(DERMIS_ERROR_INTERNAL, "out of memory");
}

void dermis_instance_destroy(dermis_instance* instance) { delete instance; }

size_t dermis_instance_memory_bytes(const dermis_instance* instance) {
  return instance ? sizeof(dermis_instance) + instance->impl->memory_bytes() : 0;
}

void dermis_instance_reset_history(dermis_instance* instance) {
  if (instance) instance->impl->ResetHistory();
}

dermis_status dermis_instance_pose(dermis_instance* instance, size_t part,
                                   const float* skin_matrices, size_t count) {
  if (!instance) return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_instance_pose: null instance");
  dermis::PoseJob job;
  job.instance = instance->impl.get();
  job.part = part;
  job.skin_matrices = skin_matrices;
  job.num_skin_matrices = count;
  if (!job.Validate()) {
    const dermis::RuntimeCharacter& c = instance->impl->character();
    if (part >= c.num_parts()) {
      return Fail(DERMIS_ERROR_INVALID_ARGUMENT,
                  "dermis_instance_pose: part " + std::to_string(part) + " does not exist");
    }
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT,
                "dermis_instance_pose: part " + std::to_string(part) + " needs " +
                    std::to_string(c.num_joints(part)) + " skin matrices, got " +
                    std::to_string(count) + (skin_matrices ? "" : " (null pointer)"));
  }
  if (!job.Run()) {
    return Fail(DERMIS_ERROR_INVALID_INPUT,
                "dermis_instance_pose: a skin matrix is not finite (pose unchanged)");
  }
  return DERMIS_OK;
}

dermis_status dermis_instance_pose_remapped(dermis_instance* instance, size_t part,
                                            const float* engine_matrices, size_t engine_count,
                                            const int32_t* remap, size_t remap_count) {
  if (!instance)
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_instance_pose_remapped: null instance");
  const dermis::RuntimeCharacter& c = instance->impl->character();
  if (part >= c.num_parts()) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT,
                "dermis_instance_pose_remapped: part " + std::to_string(part) + " does not exist");
  }
  const size_t joints = c.num_joints(part);
  if (joints == 0) return DERMIS_OK;  // static: the rest pose
  if (remap_count != joints || !remap || !engine_matrices) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT,
                "dermis_instance_pose_remapped: part " + std::to_string(part) +
                    " needs a remap of " + std::to_string(joints) + " entries, got " +
                    std::to_string(remap_count) +
                    ((remap && engine_matrices) ? "" : " (null pointer)"));
  }
  dermis::PoseJob job;
  job.instance = instance->impl.get();
  job.part = part;
  job.skin_matrices = engine_matrices;
  job.num_skin_matrices = engine_count;
  job.joint_remap = remap;
  if (!job.Validate()) {
    for (size_t j = 0; j < joints; ++j) {
      if (remap[j] < 0 || static_cast<size_t>(remap[j]) >= engine_count) {
        return Fail(DERMIS_ERROR_INVALID_ARGUMENT,
                    "dermis_instance_pose_remapped: remap[" + std::to_string(j) +
                        "] = " + std::to_string(remap[j]) + " is outside the engine's " +
                        std::to_string(engine_count) + " matrices (pose unchanged)");
      }
    }
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_instance_pose_remapped: invalid job");
  }
  if (!job.Run()) {
    return Fail(DERMIS_ERROR_INVALID_INPUT,
                "dermis_instance_pose_remapped: a skin matrix is not finite (pose unchanged)");
  }
  return DERMIS_OK;
}

namespace {

// dermis_evaluate() and dermis_evaluate_with_tangents() (`fn` names the caller in messages):
// every buffer size is checked before anything is written.
dermis_status Evaluate(const char* fn, const dermis_instance* instance, const dermis_output* output,
                       size_t block_begin, size_t block_end, float* positions,
                       size_t position_stride, size_t positions_bytes, float* normals,
                       size_t normal_stride, size_t normals_bytes, float* tangents,
                       size_t tangent_stride, size_t tangents_bytes) {
  // (Messages are built only on failure: a successful call allocates nothing.)
  if (!instance || !output) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT, std::string(fn) + ": null handle");
  }
  const size_t need_p =
      dermis_output_required_bytes(output, block_begin, block_end, position_stride);
  if (positions && positions_bytes < need_p) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT,
                std::string(fn) + ": the position buffer holds " + std::to_string(positions_bytes) +
                    " bytes, blocks [" + std::to_string(block_begin) + ", " +
                    std::to_string(std::min(block_end, dermis_output_block_count(output))) +
                    ") with stride " + std::to_string(position_stride) + " need " +
                    std::to_string(need_p) + " (nothing written)");
  }
  const size_t need_n =
      normals ? dermis_output_required_bytes(output, block_begin, block_end, normal_stride) : 0;
  if (normals && normals_bytes < need_n) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT,
                std::string(fn) + ": the normal buffer holds " + std::to_string(normals_bytes) +
                    " bytes, the range with stride " + std::to_string(normal_stride) + " needs " +
                    std::to_string(need_n) + " (nothing written)");
  }
  if (tangents) {
    if (output->impl->tangent_frames().empty()) {
      return Fail(DERMIS_ERROR_INVALID_ARGUMENT,
                  std::string(fn) +
                      ": the output was created without tangents (dermis_output_desc.tangents)");
    }
    // 4 floats at the last vertex: one float more than dermis_output_required_bytes() counts.
    size_t need_t = dermis_output_required_bytes(output, block_begin, block_end, tangent_stride);
    if (need_t > 0) need_t += sizeof(float);
    if (tangent_stride < 4 * sizeof(float) || tangents_bytes < need_t) {
      return Fail(DERMIS_ERROR_INVALID_ARGUMENT,
                  std::string(fn) + ": the tangent buffer holds " + std::to_string(tangents_bytes) +
                      " bytes, the range with stride " + std::to_string(tangent_stride) +
                      " needs " + std::to_string(need_t) +
                      " (and a stride of at least 16; nothing written)");
    }
  }
  dermis::EvaluateJob job;
  job.output = output->impl.get();
  job.instance = instance->impl.get();
  job.block_begin = block_begin;
  job.block_end = block_end;
  job.buffers.positions = positions;
  job.buffers.position_stride = position_stride;
  job.buffers.normals = normals;
  job.buffers.normal_stride = normal_stride;
  job.buffers.tangents = tangents;
  job.buffers.tangent_stride = tangent_stride;
  if (!job.Run()) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT,
                std::string(fn) +
                    ": invalid arguments (an output of another character, a block range past the "
                    "end, a null position buffer or a stride below 12 bytes)");
  }
  return DERMIS_OK;
}

}  // namespace

dermis_status dermis_evaluate(const dermis_instance* instance, const dermis_output* output,
                              size_t block_begin, size_t block_end, float* positions,
                              size_t position_stride, size_t positions_bytes, float* normals,
                              size_t normal_stride, size_t normals_bytes) {
  return Evaluate("dermis_evaluate", instance, output, block_begin, block_end, positions,
                  position_stride, positions_bytes, normals, normal_stride, normals_bytes, nullptr,
                  0, 0);
}

dermis_status dermis_output_plan(const dermis_output* o, const void** blocks, size_t* block_bytes,
                                 const float** data, size_t* data_bytes) {
  if (!o || !blocks || !block_bytes || !data || !data_bytes)
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_output_plan: null argument");
  const dermis::EvaluationPlan& plan = o->impl->plan();
  *blocks = plan.blocks();
  *block_bytes = plan.num_blocks() * sizeof(dermis::PlanBlock);
  *data = plan.block_data();
  *data_bytes = plan.num_blocks() * dermis::kPlanBlockFloats * sizeof(float);
  return DERMIS_OK;
}

dermis_status dermis_instance_packed_patches(const dermis_instance* instance, size_t part,
                                             const float** patches, size_t* floats) {
  if (!instance || !patches || !floats)
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT, "dermis_instance_packed_patches: null argument");
  const dermis::RuntimeCharacter& c = instance->impl->character();
  if (part >= c.num_parts()) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT,
                "dermis_instance_packed_patches: part " + std::to_string(part) + " does not exist");
  }
  *patches = instance->impl->packed_patches(part);
  *floats = c.num_control_vertices(part) * dermis::kPackedPatchStride;
  return DERMIS_OK;
}

}  // extern "C"

// ---- Tangents (issue 17): dermis_output_has_tangents, dermis_evaluate_with_tangents.

int32_t dermis_output_has_tangents(const dermis_output* output) {
  return output && !output->impl->tangent_frames().empty() ? 1 : 0;
}

dermis_status dermis_evaluate_with_tangents(const dermis_instance* instance,
                                            const dermis_output* output, size_t block_begin,
                                            size_t block_end, float* positions,
                                            size_t position_stride, size_t positions_bytes,
                                            float* normals, size_t normal_stride,
                                            size_t normals_bytes, float* tangents,
                                            size_t tangent_stride, size_t tangents_bytes) {
  if (!tangents) {
    return Fail(DERMIS_ERROR_INVALID_ARGUMENT,
                "dermis_evaluate_with_tangents: null tangent buffer (use dermis_evaluate)");
  }
  return Evaluate("dermis_evaluate_with_tangents", instance, output, block_begin, block_end,
                  positions, position_stride, positions_bytes, normals, normal_stride,
                  normals_bytes, tangents, tangent_stride, tangents_bytes);
}

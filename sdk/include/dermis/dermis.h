/* Copyright (c) Dermis authors. SPDX-License-Identifier: MIT */
/** \file
 * \brief The Dermis C API: the engine runtime (dermis/runtime/runtime.h) behind opaque handles,
 * for engines and languages that cannot use C++ directly. C99; link dermis::runtime (or
 * `pkg-config --libs dermis-runtime`) with a C++ linker or add -lstdc++ -lm.
 *
 * Model: load a character once (dermis_character, immutable, share it between threads);
 * create its outputs once (dermis_output: the bound vertices or a tessellation level of one
 * part, precomputed); one dermis_instance per character on screen. Per frame, per part:
 * dermis_instance_pose() with the joint palette, then dermis_evaluate() into your own vertex
 * buffers. Neither per-frame call allocates (except to record an error message).
 *
 * Errors: every function that can fail returns a dermis_status; on failure
 * dermis_last_error() gives a message for the calling thread, naming the file or argument at
 * fault. Destroy functions accept NULL. A handle must outlive nothing that was created from
 * it: destroy outputs and instances before their character.
 */
#ifndef DERMIS_DERMIS_H_
#define DERMIS_DERMIS_H_

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Result of a call. */
typedef enum dermis_status {
  DERMIS_OK = 0,
  DERMIS_ERROR_INVALID_ARGUMENT =
      1,                          /**< Null handle or pointer, index out of range, wrong count. */
  DERMIS_ERROR_INVALID_INPUT = 2, /**< A damaged or inconsistent file or data. */
  DERMIS_ERROR_IO = 3,            /**< A file that cannot be read. */
  DERMIS_ERROR_UNSUPPORTED = 4,   /**< A valid request this build cannot serve. */
  DERMIS_ERROR_INTERNAL = 5
} dermis_status;

/** Skeletal deformer of the control vertices. */
typedef enum dermis_deformer {
  DERMIS_DEFORMER_LBS = 0,  /**< Linear blend skinning. */
  DERMIS_DEFORMER_DQS = 1,  /**< Dual-quaternion skinning. */
  DERMIS_DEFORMER_SWEEP = 2 /**< The sweep-based deformer (paper section 5). */
} dermis_deformer;

/** What an output evaluates. */
typedef enum dermis_output_kind {
  DERMIS_OUTPUT_BOUND = 0, /**< The part's bound original vertices. */
  DERMIS_OUTPUT_LEVEL = 1  /**< The part's uniform tessellation at a level. */
} dermis_output_kind;

typedef struct dermis_character dermis_character;
typedef struct dermis_output dermis_output;
typedef struct dermis_instance dermis_instance;

/** Library version, "MAJOR.MINOR.PATCH". */
const char* dermis_version(void);
/** Message of the last failed call on this thread ("" if none). Valid until the next failing
 * call on this thread. */
const char* dermis_last_error(void);
/** "Ok", "invalid argument", ... */
const char* dermis_status_string(dermis_status status);

/** Loads a .dsurf (character version 2, or a plain surface version 1 as one static part). */
dermis_status dermis_character_load(const char* path, dermis_character** out);
/** The same from `size` bytes in memory (copied); `name` is used in messages (may be NULL). */
dermis_status dermis_character_load_memory(const void* bytes, size_t size, const char* name,
                                           dermis_character** out);
void dermis_character_destroy(dermis_character* character);
/** Fitted parts (surfaces) of the character; 0 for NULL. */
size_t dermis_character_part_count(const dermis_character* character);
/** Joints of the part's skin: the matrix count dermis_instance_pose() takes (0: static). */
size_t dermis_character_joint_count(const dermis_character* character, size_t part);
size_t dermis_character_control_vertex_count(const dermis_character* character, size_t part);
/** Parent of joint `joint` within the part's skin, -1 for a root (or out of range). */
int32_t dermis_character_joint_parent(const dermis_character* character, size_t part, size_t joint);
/** Bind matrix of a joint (the inverse of its inverse bind matrix: joint frame -> mesh space
 * at bind time), column-major, 16 floats into `out`. */
dermis_status dermis_character_joint_bind(const dermis_character* character, size_t part,
                                          size_t joint, float* out);
/** Original vertices bound to the part: the vertex count of a DERMIS_OUTPUT_BOUND output. */
size_t dermis_character_bound_vertex_count(const dermis_character* character, size_t part);
/** Which source vertex (glTF mesh, primitive, vertex index) bound vertex `index` is. */
dermis_status dermis_character_bound_vertex(const dermis_character* character, size_t part,
                                            size_t index, int32_t* mesh, int32_t* primitive,
                                            int32_t* vertex);

/** Settings of an output; start from dermis_output_desc_init(). */
typedef struct dermis_output_desc {
  dermis_output_kind kind;     /**< Default DERMIS_OUTPUT_LEVEL. */
  int32_t level;               /**< Segments per control-face edge, 1..64 (default 4). */
  int32_t displacement_levels; /**< -1: all (default), 0: none, n: the first n. */
  int32_t threads;             /**< Threads of the precomputation, 0: all cores (default 1). */
} dermis_output_desc;

void dermis_output_desc_init(dermis_output_desc* desc);
dermis_status dermis_output_create(const dermis_character* character, size_t part,
                                   const dermis_output_desc* desc, dermis_output** out);
void dermis_output_destroy(dermis_output* output);
size_t dermis_output_vertex_count(const dermis_output* output);
/** Triangles of a level output (0 for a bound output: use the source indices). */
size_t dermis_output_triangle_count(const dermis_output* output);
/** 3 * triangle_count vertex indices, counter-clockwise; owned by the output. */
const uint32_t* dermis_output_triangles(const dermis_output* output);
/** Blocks of up to 8 vertices: the unit in which dermis_evaluate() splits work. */
size_t dermis_output_block_count(const dermis_output* output);

/** The output's precomputed evaluation plan, for engines that evaluate it on their own GPU
 * (docs/gpu.md): `*blocks` receives the PlanBlock array (`*block_bytes` bytes, binding 0 of
 * the shader), `*data` the block floats (`*data_bytes` bytes, binding 1). Owned by the output;
 * constant for its lifetime. */
dermis_status dermis_output_plan(const dermis_output* output, const void** blocks,
                                 size_t* block_bytes, const float** data, size_t* data_bytes);

/** A posed instance of a character (starts in the rest pose). */
dermis_status dermis_instance_create(const dermis_character* character, dermis_deformer deformer,
                                     dermis_instance** out);
void dermis_instance_destroy(dermis_instance* instance);
/** Forgets the sweep's twist history (call before a pose unrelated to the previous one). */
void dermis_instance_reset_history(dermis_instance* instance);
/** Poses one part: `count` = dermis_character_joint_count() column-major 4x4 float matrices,
 * 16 floats each, world(joint) * inverseBind(joint). Deforms the control vertices and refits
 * the patches. No allocation. */
dermis_status dermis_instance_pose(dermis_instance* instance, size_t part,
                                   const float* skin_matrices, size_t count);
/** The part's packed patches of the current pose (after dermis_instance_pose()): `*floats`
 * = 32 per control vertex, the GPU shader's binding 2 (docs/gpu.md: what moves per frame).
 * Owned by the instance; rewritten by the next dermis_instance_pose() of the part. */
dermis_status dermis_instance_packed_patches(const dermis_instance* instance, size_t part,
                                             const float** patches, size_t* floats);
/** Evaluates blocks [block_begin, block_end) of `output` (block_end is clamped to the block
 * count; pass SIZE_MAX for all) with the instance's current pose: vertex i's position (3
 * floats) at positions + i * position_stride bytes, its unit normal at normals + i *
 * normal_stride (normals may be NULL). Disjoint block ranges may run on different threads at
 * once. No allocation. */
dermis_status dermis_evaluate(const dermis_instance* instance, const dermis_output* output,
                              size_t block_begin, size_t block_end, float* positions,
                              size_t position_stride, float* normals, size_t normal_stride);

#ifdef __cplusplus
}
#endif

#endif /* DERMIS_DERMIS_H_ */

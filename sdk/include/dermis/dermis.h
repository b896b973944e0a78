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
 *
 * Threads: each function states its rule as "Thread-safe" (any thread, any time, also on the
 * same handles), "Thread-safe per instance" (concurrent calls on different instances are fine;
 * one thread at a time per instance) or "Not thread-safe on the handle" (no other call may use
 * that handle meanwhile; a destroy call ends the handle's life). Characters and outputs are
 * immutable after creation, so every query on them is thread-safe.
 *
 * Linking: the static libraries (dermis::runtime, pkg-config dermis-runtime) or the shared
 * library libdermis_runtime.so (dermis::runtime_shared, pkg-config dermis-runtime-shared),
 * which exports exactly the dermis_* functions of this header. Both are position-independent,
 * so either can go into an engine plugin (docs/engine-integration.md).
 */
#ifndef DERMIS_DERMIS_H_
#define DERMIS_DERMIS_H_

#include <stddef.h>
#include <stdint.h>

/** Version of this header; dermis_version_number() gives the library's (compare them to
 * detect a header/library mismatch). The build checks these against the project version. */
#define DERMIS_VERSION_MAJOR 0
#define DERMIS_VERSION_MINOR 1
#define DERMIS_VERSION_PATCH 0
/** MAJOR * 10000 + MINOR * 100 + PATCH. */
#define DERMIS_VERSION_NUMBER \
  (DERMIS_VERSION_MAJOR * 10000 + DERMIS_VERSION_MINOR * 100 + DERMIS_VERSION_PATCH)

/* DERMIS_API marks the exported functions: default visibility in a build of the shared
 * library (which hides everything else), nothing for the static libraries or a user. */
#if defined(DERMIS_BUILDING_SHARED) && (defined(__GNUC__) || defined(__clang__))
#define DERMIS_API __attribute__((visibility("default")))
#else
#define DERMIS_API
#endif

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

/** Library version, "MAJOR.MINOR.PATCH". Thread-safe. */
DERMIS_API const char* dermis_version(void);
/** Library version as DERMIS_VERSION_NUMBER computes it (of the library actually linked or
 * loaded, which may differ from the header's). Thread-safe. */
DERMIS_API uint32_t dermis_version_number(void);
/** Message of the last failed call on this thread ("" if none). Valid until the next failing
 * call on this thread. Thread-safe (each thread has its own message). */
DERMIS_API const char* dermis_last_error(void);
/** "ok", "invalid argument", ... Thread-safe. */
DERMIS_API const char* dermis_status_string(dermis_status status);

/** Loads a .dsurf (a character, version 2, or a plain surface, versions 1 and 3, as one static
 * part). Thread-safe. */
DERMIS_API dermis_status dermis_character_load(const char* path, dermis_character** out);
/** The same from `size` bytes in memory (copied); `name` is used in messages (may be NULL).
 * Thread-safe. */
DERMIS_API dermis_status dermis_character_load_memory(const void* bytes, size_t size,
                                                      const char* name, dermis_character** out);
/** Not thread-safe on the handle; destroy its outputs and instances first. */
DERMIS_API void dermis_character_destroy(dermis_character* character);
/** Bytes the loaded character holds (its surfaces, displacements, rigs, bindings and whatever
 * of the source asset the file carries), excluding its outputs and instances; 0 for NULL.
 * Thread-safe. The queries below on a character are thread-safe too. */
DERMIS_API size_t dermis_character_memory_bytes(const dermis_character* character);
/** Fitted parts (surfaces) of the character; 0 for NULL. */
DERMIS_API size_t dermis_character_part_count(const dermis_character* character);
/** Joints of the part's skin: the matrix count dermis_instance_pose() takes (0: static). */
DERMIS_API size_t dermis_character_joint_count(const dermis_character* character, size_t part);
DERMIS_API size_t dermis_character_control_vertex_count(const dermis_character* character,
                                                        size_t part);
/** Name of joint `joint` of the part's skin (the joint node's name, "" if it has none), or
 * NULL when out of range. Owned by the character. */
DERMIS_API const char* dermis_character_joint_name(const dermis_character* character, size_t part,
                                                   size_t joint);
/** Maps the engine's skeleton onto the part's skin by joint name: `engine_names` holds the
 * engine's `engine_joint_count` joint names in its own order; on success `remap[j]` (for each
 * of the part's dermis_character_joint_count() joints j; `remap_count` must be at least that)
 * is the index in the engine's order of the joint named like skin joint j. Fails, naming the
 * first skin joint the engine lacks (or a name the engine lists twice), and writes nothing.
 * Pass the result to dermis_instance_pose_remapped(). Thread-safe. */
DERMIS_API dermis_status dermis_character_joint_remap(const dermis_character* character,
                                                      size_t part, const char* const* engine_names,
                                                      size_t engine_joint_count, int32_t* remap,
                                                      size_t remap_count);
/** Parent of joint `joint` within the part's skin, -1 for a root (or out of range). */
DERMIS_API int32_t dermis_character_joint_parent(const dermis_character* character, size_t part,
                                                 size_t joint);
/** Bind matrix of a joint (the inverse of its inverse bind matrix: joint frame -> mesh space
 * at bind time), column-major, 16 floats into `out`. */
DERMIS_API dermis_status dermis_character_joint_bind(const dermis_character* character, size_t part,
                                                     size_t joint, float* out);
/** Original vertices bound to the part: the vertex count of a DERMIS_OUTPUT_BOUND output. */
DERMIS_API size_t dermis_character_bound_vertex_count(const dermis_character* character,
                                                      size_t part);
/** Which source vertex (glTF mesh, primitive, vertex index) bound vertex `index` is. */
DERMIS_API dermis_status dermis_character_bound_vertex(const dermis_character* character,
                                                       size_t part, size_t index, int32_t* mesh,
                                                       int32_t* primitive, int32_t* vertex);

/** Settings of an output; start from dermis_output_desc_init(). */
typedef struct dermis_output_desc {
  dermis_output_kind kind;     /**< Default DERMIS_OUTPUT_LEVEL. */
  int32_t level;               /**< Segments per control-face edge, 1..64 (default 4). */
  int32_t displacement_levels; /**< -1: all (default), 0: none, n: the first n. */
  int32_t threads;             /**< Threads of the precomputation, 0: all cores (default 1). */
  int32_t tangents;            /**< 1: precompute tangent frames (bound outputs only; see "Tangents"
                                    below; 16 bytes per vertex). Default 0. */
} dermis_output_desc;

/** Thread-safe. */
DERMIS_API void dermis_output_desc_init(dermis_output_desc* desc);
/** Precomputes an output of a part (allocates; not per frame). Thread-safe: outputs of one
 * character may be created on several threads at once. The queries below on an output are
 * thread-safe. */
DERMIS_API dermis_status dermis_output_create(const dermis_character* character, size_t part,
                                              const dermis_output_desc* desc, dermis_output** out);
/** Not thread-safe on the handle. */
DERMIS_API void dermis_output_destroy(dermis_output* output);
/** Bytes the output holds (its evaluation plan and triangles); 0 for NULL. */
DERMIS_API size_t dermis_output_memory_bytes(const dermis_output* output);
DERMIS_API size_t dermis_output_vertex_count(const dermis_output* output);
/** Triangles of a level output (0 for a bound output: use the source indices). */
DERMIS_API size_t dermis_output_triangle_count(const dermis_output* output);
/** 3 * triangle_count vertex indices, counter-clockwise; owned by the output. */
DERMIS_API const uint32_t* dermis_output_triangles(const dermis_output* output);
/** Blocks of up to 8 vertices: the unit in which dermis_evaluate() splits work. */
DERMIS_API size_t dermis_output_block_count(const dermis_output* output);

/** The output's precomputed evaluation plan, for engines that evaluate it on their own GPU
 * (docs/gpu.md): `*blocks` receives the PlanBlock array (`*block_bytes` bytes, binding 0 of
 * the shader), `*data` the block floats (`*data_bytes` bytes, binding 1). Owned by the output;
 * constant for its lifetime. */
DERMIS_API dermis_status dermis_output_plan(const dermis_output* output, const void** blocks,
                                            size_t* block_bytes, const float** data,
                                            size_t* data_bytes);

/** A posed instance of a character (starts in the rest pose; allocates, not per frame).
 * Thread-safe: instances of one character may be created on several threads at once. */
DERMIS_API dermis_status dermis_instance_create(const dermis_character* character,
                                                dermis_deformer deformer, dermis_instance** out);
/** Not thread-safe on the handle. */
DERMIS_API void dermis_instance_destroy(dermis_instance* instance);
/** Bytes the instance holds (deformers, control vertices, patches of every part); 0 for NULL.
 * Thread-safe. */
DERMIS_API size_t dermis_instance_memory_bytes(const dermis_instance* instance);
/** Forgets the sweep's twist history (call before a pose unrelated to the previous one).
 * Thread-safe per instance. */
DERMIS_API void dermis_instance_reset_history(dermis_instance* instance);
/** Poses one part: `count` = dermis_character_joint_count() column-major 4x4 float matrices,
 * 16 floats each, world(joint) * inverseBind(joint). Deforms the control vertices and refits
 * the patches. No allocation. Thread-safe per instance (different parts of one instance
 * share nothing either: they may be posed on different threads at once); no evaluation of the
 * same part may run meanwhile. */
DERMIS_API dermis_status dermis_instance_pose(dermis_instance* instance, size_t part,
                                              const float* skin_matrices, size_t count);
/** dermis_instance_pose() with the engine's own palette: `engine_matrices` holds
 * `engine_count` column-major float matrices world(joint) * inverseBind(joint) in the engine's
 * joint order, and skin joint j takes engine_matrices[remap[j]] (remap from
 * dermis_character_joint_remap(); `remap_count` = dermis_character_joint_count()). An index
 * outside the engine's palette is an error and nothing changes. No allocation. Thread-safe per
 * instance, as dermis_instance_pose(). */
DERMIS_API dermis_status dermis_instance_pose_remapped(dermis_instance* instance, size_t part,
                                                       const float* engine_matrices,
                                                       size_t engine_count, const int32_t* remap,
                                                       size_t remap_count);
/** The part's packed patches of the current pose (after dermis_instance_pose()): `*floats`
 * = 32 per control vertex, the GPU shader's binding 2 (docs/gpu.md: what moves per frame).
 * Owned by the instance; rewritten by the next dermis_instance_pose() of the part.
 * Thread-safe per instance (a read: concurrent with evaluations, not with a pose of the part). */
DERMIS_API dermis_status dermis_instance_packed_patches(const dermis_instance* instance,
                                                        size_t part, const float** patches,
                                                        size_t* floats);
/** Evaluates blocks [block_begin, block_end) of `output` (block_end is clamped to the block
 * count; pass SIZE_MAX for all) with the instance's current pose: vertex i's position (3
 * floats) at positions + i * position_stride bytes, its unit normal at normals + i *
 * normal_stride (normals may be NULL). `positions_bytes` and `normals_bytes` are the sizes of
 * the buffers from `positions` and `normals` on: a buffer too small for the last vertex of the
 * range (dermis_output_required_bytes()) is an error naming both sizes, and nothing is written.
 * No allocation. Thread-safe: any number of evaluations of one instance (disjoint block
 * ranges or different outputs, into disjoint memory) may run at once, but not during a pose of
 * the part. */
DERMIS_API dermis_status dermis_evaluate(const dermis_instance* instance,
                                         const dermis_output* output, size_t block_begin,
                                         size_t block_end, float* positions, size_t position_stride,
                                         size_t positions_bytes, float* normals,
                                         size_t normal_stride, size_t normals_bytes);
/** Bytes a buffer with `stride` must hold, from vertex 0's address on, for
 * dermis_evaluate() of blocks [block_begin, block_end) (3 floats at the last vertex of the
 * range); 0 for an empty range or NULL. Thread-safe. */
DERMIS_API size_t dermis_output_required_bytes(const dermis_output* output, size_t block_begin,
                                               size_t block_end, size_t stride);

/* ---- Tangents (normal maps on bound outputs; docs/engine-integration.md, "Tangents") ----
 * A bound output created with dermis_output_desc.tangents = 1 carries each source vertex's bind
 * tangent (the glTF TANGENT, else one made from TEXCOORD_0) expressed in the displaced
 * surface's own frame at the rest pose; every frame it is re-expressed with the posed surface,
 * so it stretches and twists with the skin. At the rest pose it is the source tangent made
 * orthogonal to the surface normal. Creating such an output fails (naming the mesh and
 * primitive) when a bound vertex's primitive has neither tangents nor texture coordinates, and
 * for a DERMIS_OUTPUT_LEVEL output. */

/** 1 if the output was created with tangents, else 0 (also for NULL). Thread-safe. */
DERMIS_API int32_t dermis_output_has_tangents(const dermis_output* output);
/** dermis_evaluate() that also writes vertex i's tangent, 4 floats at tangents + i *
 * tangent_stride bytes: unit xyz orthogonal to the normal and w = +1 or -1, the bitangent
 * being cross(normal, xyz) * w (glTF's convention). `tangents_bytes` is checked like the other
 * sizes (dermis_output_required_bytes() with tangent_stride, plus 4 bytes for the fourth
 * float; tangent_stride at least 16): too small, a NULL tangent buffer or an output without
 * tangents is an error and nothing is written. No allocation. Thread-safe as
 * dermis_evaluate(). */
DERMIS_API dermis_status dermis_evaluate_with_tangents(
    const dermis_instance* instance, const dermis_output* output, size_t block_begin,
    size_t block_end, float* positions, size_t position_stride, size_t positions_bytes,
    float* normals, size_t normal_stride, size_t normals_bytes, float* tangents,
    size_t tangent_stride, size_t tangents_bytes);

#ifdef __cplusplus
}
#endif

#endif /* DERMIS_DERMIS_H_ */

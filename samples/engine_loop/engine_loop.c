/* Copyright (c) Dermis authors. SPDX-License-Identifier: MIT */
/* engine_loop: the Dermis C API in a minimal frame loop, as an engine would use it.
 *
 *   engine_loop CHARACTER.dsurf [--frames N] [--level L] [--deformer lbs|dqs|sweep]
 *                               [--gpu [DEVICE]]
 *
 * Once: load the character, create per part a tessellation output (level L) and a bound-vertex
 * output, create one instance. Per frame: build a joint palette (here a procedural wave that
 * bends every joint about its own bind frame; an engine takes it from its animation system),
 * pose every part, evaluate every output into interleaved vertex buffers (position + normal,
 * 24-byte stride) and the bound output's tangents where the source has TANGENT or TEXCOORD_0.
 * Prints per-frame timing and checks what it produced: finite positions, unit normals, unit
 * tangents orthogonal to them, the rest frame unmoved, the posed frames moved. Exit status 0 when
 * all checks hold.
 *
 * --gpu (builds with dermis::gpu, dermis/dermis_gpu.h): the evaluation runs on a Vulkan device
 * (the best one, or index DEVICE) through the reference host, which waits and copies the
 * vertices back; each frame is also evaluated on the CPU and the largest difference reported
 * and checked (positions within 1e-5 of the bounding box). Exit status 77 when
 * the machine has no Vulkan device. An engine that draws on the GPU dispatches the shader in
 * its own command buffers instead (docs/gpu.md).
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "dermis/dermis.h"
#ifdef DERMIS_ENGINE_LOOP_GPU
#include "dermis/dermis_gpu.h"
#endif

/* Column-major 4x4 float matrices: m[4 * column + row]. */
static void MatMul(const float* a, const float* b, float* out) {
  float r[16];
  for (int c = 0; c < 4; ++c) {
    for (int row = 0; row < 4; ++row) {
      float s = 0.0f;
      for (int k = 0; k < 4; ++k) s += a[4 * k + row] * b[4 * c + k];
      r[4 * c + row] = s;
    }
  }
  memcpy(out, r, sizeof(r));
}

/* Inverse of an affine matrix (last row 0 0 0 1). Returns 0 if singular. */
static int AffineInverse(const float* m, float* out) {
  const float a = m[0], b = m[4], c = m[8], d = m[1], e = m[5], f = m[9], g = m[2], h = m[6],
              i = m[10];
  const float det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
  if (fabsf(det) < 1e-30f) return 0;
  const float k = 1.0f / det;
  float r[16] = {0};
  r[0] = (e * i - f * h) * k;
  r[4] = (c * h - b * i) * k;
  r[8] = (b * f - c * e) * k;
  r[1] = (f * g - d * i) * k;
  r[5] = (a * i - c * g) * k;
  r[9] = (c * d - a * f) * k;
  r[2] = (d * h - e * g) * k;
  r[6] = (b * g - a * h) * k;
  r[10] = (a * e - b * d) * k;
  for (int row = 0; row < 3; ++row) {
    r[12 + row] = -(r[row] * m[12] + r[4 + row] * m[13] + r[8 + row] * m[14]);
  }
  r[15] = 1.0f;
  memcpy(out, r, sizeof(r));
  return 1;
}

static void RotationZ(float angle, float* out) {
  memset(out, 0, 16 * sizeof(float));
  out[0] = cosf(angle);
  out[1] = sinf(angle);
  out[4] = -sinf(angle);
  out[5] = cosf(angle);
  out[10] = out[15] = 1.0f;
}

/* The palette of one frame: joint j's world matrix is world(parent) * bind(parent)^-1 *
 * bind(j) * R(angle_j), so at angle 0 it is bind(j) and the skin matrix world * bind^-1 is the
 * identity. Joints must come after their parents or have none (glTF does not promise that, so
 * parents are resolved recursively). */
typedef struct Rig {
  size_t joints;
  const int32_t* parent;
  const float* bind;    /* 16 per joint */
  const float* inverse; /* 16 per joint */
} Rig;

static void WorldOf(const Rig* rig, size_t j, float t, float* world, int* done) {
  if (done[j]) return;
  float local[16], rot[16];
  RotationZ(0.35f * sinf(t + 0.7f * (float)j), rot);
  const int32_t p = rig->parent[j];
  if (p >= 0 && (size_t)p < rig->joints) {
    WorldOf(rig, (size_t)p, t, world, done);
    MatMul(rig->inverse + 16 * (size_t)p, rig->bind + 16 * j, local); /* parent -> joint */
    MatMul(local, rot, local);
    MatMul(world + 16 * (size_t)p, local, world + 16 * j);
  } else {
    MatMul(rig->bind + 16 * j, rot, world + 16 * j);
  }
  done[j] = 1;
}

static double Now(void) {
  struct timespec ts;
  timespec_get(&ts, TIME_UTC);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#define CHECK(call)                                                                            \
  do {                                                                                         \
    dermis_status s_ = (call);                                                                 \
    if (s_ != DERMIS_OK) {                                                                     \
      fprintf(stderr, "engine_loop: %s: %s\n", dermis_status_string(s_), dermis_last_error()); \
      return 1;                                                                                \
    }                                                                                          \
  } while (0)

typedef struct Part {
  dermis_output* outputs[2]; /* level, bound */
#ifdef DERMIS_ENGINE_LOOP_GPU
  dermis_gpu_output* gpu_outputs[2];
  float* cpu_check[2]; /* the CPU's result, to compare with the GPU's */
#endif
  float* buffers[2]; /* 6 floats per vertex */
  float* tangents;   /* the bound output's tangents, 4 floats per vertex (NULL: none) */
  size_t tangent_bytes;
  float* rest[2];
  size_t bytes[2]; /* size of buffers[o] */
  size_t vertices[2];
  Rig rig;
  float* palette;
  float* world;
  int* done;
  /* The engine's own skeleton: its joints in another order (here the skin's reversed) and the
   * palette in that order; remap[j] = the engine's index of skin joint j, matched by name. */
  float* engine_palette;
  int32_t* remap;
} Part;

#ifdef DERMIS_ENGINE_LOOP_GPU
/* Largest |a - b| over positions (relative to the bounding-box diagonal of b) and normals of
 * n interleaved vertices, and the count of normals that differ by more than 1e-4. */
static void Difference(const float* a, const float* b, size_t n, double* position, double* normal,
                       size_t* normals_over) {
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = fminf(lo[k], b[6 * i + k]);
      hi[k] = fmaxf(hi[k], b[6 * i + k]);
    }
  }
  double diag = 0.0;
  for (int k = 0; k < 3; ++k) diag += (double)(hi[k] - lo[k]) * (double)(hi[k] - lo[k]);
  diag = diag > 0.0 ? sqrt(diag) : 1.0;
  for (size_t i = 0; i < n; ++i) {
    double dp = 0.0, dn = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double p = (double)a[6 * i + k] - b[6 * i + k];
      const double q = (double)a[6 * i + 3 + k] - b[6 * i + 3 + k];
      dp += p * p;
      dn += q * q;
    }
    if (!(sqrt(dp) / diag <= *position)) *position = sqrt(dp) / diag; /* NaN propagates */
    if (!(sqrt(dn) <= *normal)) *normal = sqrt(dn);
    if (!(sqrt(dn) <= 1e-4)) ++*normals_over;
  }
}
#endif

int main(int argc, char** argv) {
  const char* path = NULL;
  int frames = 60, level = 6;
  int use_gpu = 0, gpu_device = -1;
  dermis_deformer deformer = DERMIS_DEFORMER_SWEEP;
  for (int i = 1; i < argc; ++i) {
    if (!strcmp(argv[i], "--gpu")) {
      use_gpu = 1;
      if (i + 1 < argc && argv[i + 1][0] >= '0' && argv[i + 1][0] <= '9') {
        gpu_device = atoi(argv[++i]);
      }
    } else if (!strcmp(argv[i], "--frames") && i + 1 < argc) {
      frames = atoi(argv[++i]);
    } else if (!strcmp(argv[i], "--level") && i + 1 < argc) {
      level = atoi(argv[++i]);
    } else if (!strcmp(argv[i], "--deformer") && i + 1 < argc) {
      const char* d = argv[++i];
      deformer = !strcmp(d, "lbs")   ? DERMIS_DEFORMER_LBS
                 : !strcmp(d, "dqs") ? DERMIS_DEFORMER_DQS
                                     : DERMIS_DEFORMER_SWEEP;
    } else if (argv[i][0] != '-' && !path) {
      path = argv[i];
    } else {
      fprintf(stderr,
              "usage: engine_loop CHARACTER.dsurf [--frames N] [--level L] "
              "[--deformer lbs|dqs|sweep] [--gpu [DEVICE]]\n");
      return 2;
    }
  }
  if (!path || frames < 1) {
    fprintf(stderr,
            "usage: engine_loop CHARACTER.dsurf [--frames N] [--level L] "
            "[--deformer lbs|dqs|sweep] [--gpu [DEVICE]]\n");
    return 2;
  }
#ifndef DERMIS_ENGINE_LOOP_GPU
  if (use_gpu) {
    fprintf(stderr, "engine_loop: --gpu: this build has no GPU evaluation (DERMIS_BUILD_GPU)\n");
    return 2;
  }
  (void)gpu_device;
#else
  dermis_gpu_context* gpu = NULL;
  if (use_gpu) {
    const dermis_status gs = dermis_gpu_context_create(gpu_device, &gpu);
    if (gs == DERMIS_ERROR_UNSUPPORTED) {
      printf("engine_loop: SKIPPED the GPU: %s\n", dermis_last_error());
      return 77;
    }
    CHECK(gs);
    printf("GPU: %s\n", dermis_gpu_device_name(gpu));
  }
#endif
  printf("dermis %s\n", dermis_version());
  dermis_character* character = NULL;
  CHECK(dermis_character_load(path, &character));
  const size_t parts = dermis_character_part_count(character);
  Part* part = calloc(parts, sizeof(Part));
  if (!part) return 1;
  size_t total_vertices = 0;
  for (size_t p = 0; p < parts; ++p) {
    dermis_output_desc desc;
    dermis_output_desc_init(&desc);
    desc.level = level;
    desc.threads = 0;
    CHECK(dermis_output_create(character, p, &desc, &part[p].outputs[0]));
    desc.kind = DERMIS_OUTPUT_BOUND;
    /* Tangents for normal maps where the source has TANGENT or TEXCOORD_0. */
    desc.tangents = 1;
    if (dermis_output_create(character, p, &desc, &part[p].outputs[1]) != DERMIS_OK) {
      printf("part %zu: bound output without tangents (%s)\n", p, dermis_last_error());
      desc.tangents = 0;
      CHECK(dermis_output_create(character, p, &desc, &part[p].outputs[1]));
    }
    if (dermis_output_has_tangents(part[p].outputs[1])) {
      const size_t n = dermis_output_vertex_count(part[p].outputs[1]);
      part[p].tangent_bytes = (4 * n + 1) * sizeof(float);
      part[p].tangents = calloc(4 * n + 1, sizeof(float));
      if (!part[p].tangents) return 1;
    }
    for (int o = 0; o < 2; ++o) {
      const size_t n = dermis_output_vertex_count(part[p].outputs[o]);
      part[p].vertices[o] = n;
      part[p].bytes[o] = (6 * n + 1) * sizeof(float);
      part[p].buffers[o] = calloc(6 * n + 1, sizeof(float));
      part[p].rest[o] = calloc(6 * n + 1, sizeof(float));
      if (!part[p].buffers[o] || !part[p].rest[o]) return 1;
#ifdef DERMIS_ENGINE_LOOP_GPU
      if (gpu) {
        /* Once: the output's plan to the device. */
        CHECK(dermis_gpu_output_create(gpu, part[p].outputs[o], &part[p].gpu_outputs[o]));
        part[p].cpu_check[o] = calloc(6 * n + 1, sizeof(float));
        if (!part[p].cpu_check[o]) return 1;
      }
#endif
      total_vertices += n;
    }
    Rig* rig = &part[p].rig;
    rig->joints = dermis_character_joint_count(character, p);
    int32_t* parent = calloc(rig->joints + 1, sizeof(int32_t));
    float* bind = calloc(16 * rig->joints + 1, sizeof(float));
    float* inverse = calloc(16 * rig->joints + 1, sizeof(float));
    part[p].palette = calloc(16 * rig->joints + 1, sizeof(float));
    part[p].world = calloc(16 * rig->joints + 1, sizeof(float));
    part[p].done = calloc(rig->joints + 1, sizeof(int));
    if (!parent || !bind || !inverse || !part[p].palette || !part[p].world || !part[p].done)
      return 1;
    for (size_t j = 0; j < rig->joints; ++j) {
      parent[j] = dermis_character_joint_parent(character, p, j);
      CHECK(dermis_character_joint_bind(character, p, j, bind + 16 * j));
      if (!AffineInverse(bind + 16 * j, inverse + 16 * j)) {
        fprintf(stderr, "engine_loop: %s: joint %zu has a singular bind matrix\n", path, j);
        return 1;
      }
    }
    rig->parent = parent;
    rig->bind = bind;
    rig->inverse = inverse;
    /* The engine's skeleton lists the joints by name in its own order; the remap is built
     * once, by name, and every frame poses with the engine's palette as it is. */
    part[p].engine_palette = calloc(16 * rig->joints + 1, sizeof(float));
    part[p].remap = calloc(rig->joints + 1, sizeof(int32_t));
    const char** engine_names = calloc(rig->joints + 1, sizeof(char*));
    if (!part[p].engine_palette || !part[p].remap || !engine_names) return 1;
    for (size_t j = 0; j < rig->joints; ++j) {
      engine_names[rig->joints - 1 - j] = dermis_character_joint_name(character, p, j);
    }
    CHECK(dermis_character_joint_remap(character, p, engine_names, rig->joints, part[p].remap,
                                       rig->joints));
    free(engine_names);
    printf(
        "part %zu: %zu control vertices, %zu joints, level %d: %zu vertices %zu triangles, "
        "bound: %zu vertices%s\n",
        p, dermis_character_control_vertex_count(character, p), rig->joints, level,
        part[p].vertices[0], dermis_output_triangle_count(part[p].outputs[0]), part[p].vertices[1],
        part[p].tangents ? " with tangents" : "");
  }
  dermis_instance* instance = NULL;
  CHECK(dermis_instance_create(character, deformer, &instance));
  {
    size_t output_bytes = 0;
    for (size_t p = 0; p < parts; ++p) {
      output_bytes += dermis_output_memory_bytes(part[p].outputs[0]) +
                      dermis_output_memory_bytes(part[p].outputs[1]);
    }
    printf("memory: character %.3f MB, outputs %.3f MB, instance %.3f MB\n",
           1e-6 * (double)dermis_character_memory_bytes(character), 1e-6 * (double)output_bytes,
           1e-6 * (double)dermis_instance_memory_bytes(instance));
  }

  double pose_time = 0.0, eval_time = 0.0, max_motion = 0.0;
  double gpu_position = 0.0, gpu_normal = 0.0;
  size_t gpu_normals_over = 0, gpu_compared = 0;
  int failures = 0;
  for (int f = 0; f <= frames; ++f) {
    const float t = 0.1f * (float)f;
    double t0 = Now();
    for (size_t p = 0; p < parts; ++p) {
      const Rig* rig = &part[p].rig;
      memset(part[p].done, 0, rig->joints * sizeof(int));
      for (size_t j = 0; j < rig->joints; ++j) WorldOf(rig, j, t, part[p].world, part[p].done);
      for (size_t j = 0; j < rig->joints; ++j) {
        MatMul(part[p].world + 16 * j, rig->inverse + 16 * j, part[p].palette + 16 * j);
      }
      if (f == 0) {
        /* The rest frame: identity skin matrices exactly. */
        for (size_t j = 0; j < rig->joints; ++j) {
          memset(part[p].palette + 16 * j, 0, 16 * sizeof(float));
          for (int k = 0; k < 4; ++k) part[p].palette[16 * j + 5 * k] = 1.0f;
        }
      }
      /* The engine's palette is in its own joint order. */
      for (size_t j = 0; j < rig->joints; ++j) {
        memcpy(part[p].engine_palette + 16 * part[p].remap[j], part[p].palette + 16 * j,
               16 * sizeof(float));
      }
      CHECK(dermis_instance_pose_remapped(instance, p, part[p].engine_palette, rig->joints,
                                          part[p].remap, rig->joints));
    }
    double t1 = Now();
    for (size_t p = 0; p < parts; ++p) {
      for (int o = 0; o < 2; ++o) {
        float* b = part[p].buffers[o];
#ifdef DERMIS_ENGINE_LOOP_GPU
        if (gpu) {
          CHECK(dermis_gpu_evaluate(part[p].gpu_outputs[o], instance, b, 24, b + 3, 24));
          continue;
        }
#endif
        if (o == 1 && part[p].tangents) {
          CHECK(dermis_evaluate_with_tangents(instance, part[p].outputs[o], 0, SIZE_MAX, b, 24,
                                              part[p].bytes[o], b + 3, 24, part[p].bytes[o] - 12,
                                              part[p].tangents, 16, part[p].tangent_bytes));
        } else {
          CHECK(dermis_evaluate(instance, part[p].outputs[o], 0, SIZE_MAX, b, 24, part[p].bytes[o],
                                b + 3, 24, part[p].bytes[o] - 12));
        }
      }
    }
    double t2 = Now();
#ifdef DERMIS_ENGINE_LOOP_GPU
    if (gpu) {
      for (size_t p = 0; p < parts; ++p) {
        for (int o = 0; o < 2; ++o) {
          float* c = part[p].cpu_check[o];
          CHECK(dermis_evaluate(instance, part[p].outputs[o], 0, SIZE_MAX, c, 24, part[p].bytes[o],
                                c + 3, 24, part[p].bytes[o] - 12));
          Difference(part[p].buffers[o], c, part[p].vertices[o], &gpu_position, &gpu_normal,
                     &gpu_normals_over);
          gpu_compared += part[p].vertices[o];
        }
      }
    }
#endif
    if (f > 0) {
      pose_time += t1 - t0;
      eval_time += t2 - t1;
    }
    for (size_t p = 0; p < parts; ++p) {
      for (int o = 0; o < 2; ++o) {
        const float* b = part[p].buffers[o];
        for (size_t i = 0; i < part[p].vertices[o]; ++i) {
          const float* v = b + 6 * i;
          const float len = sqrtf(v[3] * v[3] + v[4] * v[4] + v[5] * v[5]);
          if (!isfinite(v[0]) || !isfinite(v[1]) || !isfinite(v[2]) || fabsf(len - 1.0f) > 1e-4f) {
            if (failures++ < 5)
              fprintf(stderr, "engine_loop: frame %d part %zu vertex %zu: bad output\n", f, p, i);
          }
          /* Tangents: unit, orthogonal to the normal, w = +-1. */
          if (o == 1 && part[p].tangents) {
            const float* tg = part[p].tangents + 4 * i;
            const float tl = sqrtf(tg[0] * tg[0] + tg[1] * tg[1] + tg[2] * tg[2]);
            const float tn = (tg[0] * v[3] + tg[1] * v[4] + tg[2] * v[5]) / len;
            if (fabsf(tl - 1.0f) > 1e-4f || fabsf(tn) > 1e-4f || fabsf(fabsf(tg[3]) - 1.0f) > 0) {
              if (failures++ < 5)
                fprintf(stderr, "engine_loop: frame %d part %zu vertex %zu: bad tangent\n", f, p,
                        i);
            }
          }
          if (f == 0) continue;
          const float* r = part[p].rest[o] + 6 * i;
          const double d =
              sqrt((double)((v[0] - r[0]) * (v[0] - r[0]) + (v[1] - r[1]) * (v[1] - r[1]) +
                            (v[2] - r[2]) * (v[2] - r[2])));
          if (d > max_motion) max_motion = d;
        }
        if (f == 0) memcpy(part[p].rest[o], b, 6 * part[p].vertices[o] * sizeof(float));
      }
    }
  }
  /* A second rest frame after the loop gives the first one back (up to float rounding). */
  dermis_instance_reset_history(instance);
  double rest_error = 0.0;
  for (size_t p = 0; p < parts; ++p) {
    const Rig* rig = &part[p].rig;
    for (size_t j = 0; j < rig->joints; ++j) {
      memset(part[p].palette + 16 * j, 0, 16 * sizeof(float));
      for (int k = 0; k < 4; ++k) part[p].palette[16 * j + 5 * k] = 1.0f;
    }
    CHECK(dermis_instance_pose(instance, p, part[p].palette, rig->joints));
    float* b = part[p].buffers[1];
#ifdef DERMIS_ENGINE_LOOP_GPU
    if (gpu) {
      CHECK(dermis_gpu_evaluate(part[p].gpu_outputs[1], instance, b, 24, b + 3, 24));
    } else
#endif
      CHECK(dermis_evaluate(instance, part[p].outputs[1], 0, SIZE_MAX, b, 24, part[p].bytes[1],
                            b + 3, 24, part[p].bytes[1] - 12));
    for (size_t i = 0; i < 6 * part[p].vertices[1]; ++i) {
      const double d = fabs((double)(b[i] - part[p].rest[1][i]));
      if (d > rest_error) rest_error = d;
    }
  }
  /* Bad calls fail cleanly with a message; an undersized buffer is refused, nothing written. */
  if (parts > 0 && part[0].vertices[0] > 1) {
    float* b = part[0].buffers[0];
    b[0] = -12345.0f;
    const dermis_status s =
        dermis_evaluate(instance, part[0].outputs[0], 0, SIZE_MAX, b, 24, 12, NULL, 0, 0);
    if (s != DERMIS_ERROR_INVALID_ARGUMENT || b[0] != -12345.0f) {
      fprintf(stderr, "engine_loop: an undersized buffer was not refused\n");
      ++failures;
    }
  }
  /* Bad calls fail cleanly with a message. */
  if (dermis_instance_pose(instance, parts, NULL, 0) != DERMIS_ERROR_INVALID_ARGUMENT ||
      strlen(dermis_last_error()) == 0) {
    fprintf(stderr, "engine_loop: a pose of a missing part was not refused\n");
    ++failures;
  }
  printf(
      "%d frames, %zu output vertices per frame: pose %.3f ms, evaluate %.3f ms per frame "
      "(%.1f M vertices/s); largest motion from rest %.4g; rest pose again: max difference "
      "%.3g\n",
      frames, total_vertices, 1e3 * pose_time / frames, 1e3 * eval_time / frames,
      (double)total_vertices * frames / (pose_time + eval_time) * 1e-6, max_motion, rest_error);
  int posed_parts = 0;
  for (size_t p = 0; p < parts; ++p) posed_parts += part[p].rig.joints > 0;
  if (posed_parts > 0 && !(max_motion > 0.0)) {
    fprintf(stderr, "engine_loop: the posed frames did not move\n");
    ++failures;
  }
  if (rest_error > 1e-4) {
    fprintf(stderr, "engine_loop: the rest pose is not reproduced (%.3g)\n", rest_error);
    ++failures;
  }
  if (use_gpu) {
    /* Positions agree within float rounding. Normals can differ more where the surface is
     * nearly degenerate: dermis_evaluate() runs the AVX2 kernel where the CPU has it, which
     * fuses multiply-adds, while the shader repeats the portable kernel's rounding
     * (docs/gpu.md, section 8; tests/gpu compares the two kernels separately). */
    printf(
        "GPU against the CPU: largest difference %.3g of the bounding box (positions), %.3g "
        "(normals; %zu of %zu vertices over 1e-4)\n",
        gpu_position, gpu_normal, gpu_normals_over, gpu_compared);
    if (!(gpu_position < 1e-5)) {
      fprintf(stderr, "engine_loop: the GPU's positions differ from the CPU's\n");
      ++failures;
    }
  }
  for (size_t p = 0; p < parts; ++p) {
    for (int o = 0; o < 2; ++o) {
#ifdef DERMIS_ENGINE_LOOP_GPU
      dermis_gpu_output_destroy(part[p].gpu_outputs[o]);
      free(part[p].cpu_check[o]);
#endif
      dermis_output_destroy(part[p].outputs[o]);
      free(part[p].buffers[o]);
      free(part[p].rest[o]);
    }
    free(part[p].tangents);
    free((void*)part[p].rig.parent);
    free((void*)part[p].rig.bind);
    free((void*)part[p].rig.inverse);
    free(part[p].palette);
    free(part[p].engine_palette);
    free(part[p].remap);
    free(part[p].world);
    free(part[p].done);
  }
  free(part);
  dermis_instance_destroy(instance);
  dermis_character_destroy(character);
#ifdef DERMIS_ENGINE_LOOP_GPU
  dermis_gpu_context_destroy(gpu);
#endif
  if (failures) {
    fprintf(stderr, "engine_loop: %d check(s) failed\n", failures);
    return 1;
  }
  printf("engine_loop: ok\n");
  return 0;
}

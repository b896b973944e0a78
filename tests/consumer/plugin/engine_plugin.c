/* Copyright (c) Dermis authors. SPDX-License-Identifier: MIT */
/* A minimal engine plugin over the Dermis C API (tests/consumer/plugin/CMakeLists.txt): one
 * exported entry point that loads a character, maps an engine skeleton onto it by joint name,
 * and runs frames of pose + evaluate into engine-owned buffers. Each frame moves every joint by
 * the same translation, so every output vertex must move by exactly that translation (a rigid
 * motion is reproduced by every deformer): the plugin checks it and returns the largest error.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dermis/dermis.h"

#define PLUGIN_EXPORT __attribute__((visibility("default")))

static int Report(const char* what) {
  fprintf(stderr, "engine_plugin: %s: %s\n", what, dermis_last_error());
  return 1;
}

/* Returns 0 when every frame evaluated and moved rigidly; *largest_error receives the largest
 * deviation from the exact translation, *vertices the vertices evaluated per frame. */
PLUGIN_EXPORT int engine_plugin_run(const char* path, int frames, double* largest_error,
                                    size_t* vertices) {
  if (dermis_version_number() != DERMIS_VERSION_NUMBER) {
    fprintf(stderr, "engine_plugin: header %d, library %u\n", DERMIS_VERSION_NUMBER,
            (unsigned)dermis_version_number());
    return 1;
  }
  dermis_character* character = NULL;
  if (dermis_character_load(path, &character) != DERMIS_OK) return Report("load");
  dermis_instance* instance = NULL;
  if (dermis_instance_create(character, DERMIS_DEFORMER_LBS, &instance) != DERMIS_OK)
    return Report("instance");
  int failed = 0;
  double worst = 0.0;
  size_t total = 0;
  for (size_t p = 0; p < dermis_character_part_count(character) && !failed; ++p) {
    dermis_output_desc desc;
    dermis_output_desc_init(&desc);
    desc.level = 3;
    dermis_output* output = NULL;
    if (dermis_output_create(character, p, &desc, &output) != DERMIS_OK) {
      failed = Report("output");
      break;
    }
    const size_t n = dermis_output_vertex_count(output);
    const size_t joints = dermis_character_joint_count(character, p);
    /* The engine's skeleton: the skin's joints in reverse order, plus one joint of its own. */
    const size_t engine_joints = joints + 1;
    const char** names = calloc(engine_joints, sizeof(char*));
    int32_t* remap = calloc(joints + 1, sizeof(int32_t));
    float* palette = calloc(16 * engine_joints, sizeof(float));
    float* rest = calloc(6 * n + 1, sizeof(float));
    float* posed = calloc(6 * n + 1, sizeof(float));
    const size_t bytes = (6 * n + 1) * sizeof(float);
    if (!names || !remap || !palette || !rest || !posed) return 1;
    for (size_t j = 0; j < joints; ++j)
      names[joints - 1 - j] = dermis_character_joint_name(character, p, j);
    names[joints] = "engine_only_joint";
    if (dermis_character_joint_remap(character, p, names, engine_joints, remap, joints) !=
        DERMIS_OK) {
      failed = Report("remap");
    }
    for (int f = 0; f <= frames && !failed; ++f) {
      const float t[3] = {0.01f * (float)f, -0.02f * (float)f, 0.005f * (float)f};
      for (size_t j = 0; j < engine_joints; ++j) {
        float* m = palette + 16 * j;
        memset(m, 0, 16 * sizeof(float));
        for (int k = 0; k < 4; ++k) m[5 * k] = 1.0f;
        m[12] = t[0];
        m[13] = t[1];
        m[14] = t[2];
      }
      if (joints > 0 && dermis_instance_pose_remapped(instance, p, palette, engine_joints, remap,
                                                      joints) != DERMIS_OK) {
        failed = Report("pose");
        break;
      }
      float* out = f == 0 ? rest : posed;
      if (dermis_evaluate(instance, output, 0, SIZE_MAX, out, 24, bytes, out + 3, 24, bytes - 12) !=
          DERMIS_OK) {
        failed = Report("evaluate");
        break;
      }
      for (size_t i = 0; i < n && f > 0; ++i) {
        for (int k = 0; k < 3; ++k) {
          const double moved = (double)posed[6 * i + k] - (double)rest[6 * i + k];
          const double e = fabs(moved - (joints > 0 ? (double)t[k] : 0.0));
          if (!(e <= worst)) worst = e; /* NaN makes it NaN */
        }
      }
    }
    total += n;
    free(names);
    free(remap);
    free(palette);
    free(rest);
    free(posed);
    dermis_output_destroy(output);
  }
  dermis_instance_destroy(instance);
  dermis_character_destroy(character);
  *largest_error = worst;
  *vertices = total;
  return failed;
}

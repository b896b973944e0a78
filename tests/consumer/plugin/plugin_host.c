/* Copyright (c) Dermis authors. SPDX-License-Identifier: MIT */
/* The host side of the plugin test: loads an engine plugin (a shared object linking the Dermis
 * runtime) with dlopen, as an engine loads its native plugins, and runs its frames.
 *   plugin_host PLUGIN.so CHARACTER.dsurf FRAMES
 * Prints "plugin ok" and exits 0 when the plugin ran and every frame moved rigidly. */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef int (*RunFn)(const char*, int, double*, size_t*);

int main(int argc, char** argv) {
  if (argc != 4) {
    fprintf(stderr, "usage: plugin_host PLUGIN.so CHARACTER.dsurf FRAMES\n");
    return 2;
  }
  void* plugin = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
  if (!plugin) {
    fprintf(stderr, "plugin_host: %s\n", dlerror());
    return 1;
  }
  RunFn run = NULL;
  void* symbol = dlsym(plugin, "engine_plugin_run");
  memcpy(&run, &symbol, sizeof(run)); /* POSIX: a data pointer holds the function's address */
  if (!symbol) {
    fprintf(stderr, "plugin_host: %s\n", dlerror());
    return 1;
  }
  double error = -1.0;
  size_t vertices = 0;
  const int frames = atoi(argv[3]);
  if (run(argv[2], frames, &error, &vertices) != 0) return 1;
  printf("plugin: %d frames of %zu vertices, largest deviation from the rigid motion %.3g\n",
         frames, vertices, error);
  if (!(error < 1e-5) || vertices == 0) return 1;
  if (dlclose(plugin) != 0) {
    fprintf(stderr, "plugin_host: dlclose: %s\n", dlerror());
    return 1;
  }
  printf("plugin ok\n");
  return 0;
}

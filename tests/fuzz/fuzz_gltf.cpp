// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// libFuzzer harness: the glTF importer (tinygltf behind our document, depth, budget and index
// checks), as .glb when the input starts with the GLB magic, else as .gltf (docs/reliability.md).
#include <cstdio>
#include <cstring>

#include "dermis/plugins/gltf.h"
#include "fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const std::string path = dermis::fuzz::WriteInput(data, size, glb ? ".glb" : ".gltf");
  if (path.empty()) return 0;
  dermis::Asset asset;
  std::string dsurf;
  (void)dermis::ImportGltf(path, &asset, &dsurf);
  std::remove(path.c_str());
  return 0;
}

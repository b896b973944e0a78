// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// libFuzzer harness: the Assimp importer (our guards, Assimp, the scene converter). The first
// byte picks the extension the file gets, so each input reaches one of the formats users give
// the tool; the rest is the file (docs/reliability.md).
#include <cstdio>
#include <iterator>

#include "dermis/plugins/assimp.h"
#include "fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const char* const kExtensions[] = {".dae", ".fbx", ".stl",  ".3ds", ".x",
                                            ".off", ".bvh", ".ms3d", ".ase", ".bin"};
  if (size < 1) return 0;
  const char* ext = kExtensions[data[0] % std::size(kExtensions)];
  const std::string path = dermis::fuzz::WriteInput(data + 1, size - 1, ext);
  if (path.empty()) return 0;
  dermis::Asset asset;
  (void)dermis::ImportAssimp(path, &asset);
  std::remove(path.c_str());
  return 0;
}

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The importers that take a path (tinygltf, Assimp) read the fuzz input from a file of this
// process: one name per process and extension, rewritten for every input.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

namespace dermis::fuzz {

inline std::string WriteInput(const std::uint8_t* data, std::size_t size, const std::string& ext) {
  const char* dir = std::getenv("TMPDIR");
  const std::string path = std::string(dir != nullptr ? dir : "/tmp") + "/dermis_fuzz_" +
                           std::to_string(::getpid()) + ext;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return {};
  const bool ok = std::fwrite(data, 1, size, f) == size;
  std::fclose(f);
  return ok ? path : std::string();
}

}  // namespace dermis::fuzz

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The .dsurf harnesses rewrite the trailing checksum (FNV-1a 64 of everything before it,
// docs/file-format.md) so that mutations reach the body readers instead of stopping at the
// checksum test. An input of fewer than 8 bytes is passed as it is.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace dermis::fuzz {

inline std::string WithChecksum(const std::uint8_t* data, std::size_t size) {
  std::string bytes(reinterpret_cast<const char*>(data), size);
  if (size < 8) return bytes;
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (std::size_t i = 0; i < size - 8; ++i) {
    h ^= static_cast<unsigned char>(bytes[i]);
    h *= 0x100000001b3ull;
  }
  for (int k = 0; k < 8; ++k) {
    bytes[size - 8 + static_cast<std::size_t>(k)] = static_cast<char>((h >> (8 * k)) & 0xff);
  }
  return bytes;
}

}  // namespace dermis::fuzz

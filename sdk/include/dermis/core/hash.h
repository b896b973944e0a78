// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief A fixed integer hash for reproducible choices (held-out and validation splits, check
/// points, temporary file names): the same bits on every machine and thread count.
#pragma once

#include <cstdint>

namespace dermis {

/// SplitMix64's finaliser (Steele, Lea and Flood 2014, the mixer of Java's SplittableRandom):
/// x plus the golden-ratio increment, mixed into well-spread bits. A bijection of 64-bit words.
inline std::uint64_t SplitMix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// A number in [0, 1) from the top 53 bits of a hash.
inline double HashToUnit(std::uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

}  // namespace dermis

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Test support: deterministic random numbers (header only, no module).
#pragma once

#include <cstdint>

namespace dermis::test {

/// Deterministic uniform numbers in [0, 1).
class Lcg {
 public:
  explicit Lcg(std::uint64_t seed) : state_(seed * 2862933555777941757ULL + 3037000493ULL) {}
  double Next() {
    state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state_ >> 11) * (1.0 / 9007199254740992.0);
  }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Next(); }

 private:
  std::uint64_t state_;
};

}  // namespace dermis::test

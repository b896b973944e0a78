// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The table of CPU kernel backends (kernels.h), chosen at run time by what the CPU supports.
#include "runtime/kernels/kernels.h"

namespace dermis::kernels {
namespace {

bool Always() { return true; }

#if defined(__x86_64__)
bool HasAvx2() { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }
#endif

constexpr Backend kBackends[] = {
    {SimdPath::kScalar, EvaluateBlocksScalar, Always},
    {SimdPath::kGeneric, EvaluateBlocksGeneric, Always},
#if defined(__x86_64__)
    {SimdPath::kAvx2, EvaluateBlocksAvx2, HasAvx2},
#endif
};

}  // namespace

const Backend* Backends(std::size_t* count) {
  *count = sizeof(kBackends) / sizeof(kBackends[0]);
  return kBackends;
}

const Backend* FindBackend(SimdPath path) {
  const Backend* found = nullptr;
  for (const Backend& b : kBackends) {
    if ((path == SimdPath::kAuto || b.path == path) && b.available()) found = &b;
  }
  return found;
}

}  // namespace dermis::kernels

// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Static-partition parallel loop (std::thread; no TBB needed for these coarse loops).
#include "dermis/core/parallel.h"

#include <algorithm>
#include <thread>
#include <vector>

namespace dermis {

int ResolveThreadCount(int requested) {
  if (requested > 0) return requested;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : static_cast<int>(hw);
}

void ParallelFor(int threads, std::size_t count,
                 const std::function<void(std::size_t begin, std::size_t end)>& fn) {
  if (count == 0) return;
  const std::size_t n =
      std::min<std::size_t>(static_cast<std::size_t>(std::max(threads, 1)), count);
  if (n == 1) {
    fn(0, count);
    return;
  }
  std::vector<std::thread> workers;
  workers.reserve(n - 1);
  for (std::size_t t = 1; t < n; ++t) {
    workers.emplace_back(fn, count * t / n, count * (t + 1) / n);
  }
  fn(0, count / n);
  for (std::thread& w : workers) w.join();
}

}  // namespace dermis

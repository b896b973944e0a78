// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/core/parallel.h"

#include <atomic>
#include <catch2/catch.hpp>
#include <mutex>
#include <utility>
#include <vector>

using namespace dermis;

TEST_CASE("parallel: chunks are disjoint, contiguous and cover the range") {
  for (int threads : {1, 2, 3, 7, 16}) {
    for (std::size_t count : {0u, 1u, 2u, 5u, 16u, 1000u}) {
      std::mutex m;
      std::vector<std::pair<std::size_t, std::size_t>> chunks;
      std::vector<int> hits(count, 0);
      ParallelFor(threads, count, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) ++hits[i];
        std::lock_guard<std::mutex> lock(m);
        chunks.emplace_back(begin, end);
      });
      INFO("threads " << threads << " count " << count);
      for (int h : hits) CHECK(h == 1);
      // One chunk per thread at most, each [count t / n, count (t + 1) / n).
      const std::size_t n = std::min<std::size_t>(static_cast<std::size_t>(threads), count);
      CHECK(chunks.size() == n);
      for (const auto& [b, e] : chunks) {
        bool found = false;
        for (std::size_t t = 0; t < n; ++t) found |= b == count * t / n && e == count * (t + 1) / n;
        CHECK(found);
      }
    }
  }
}

TEST_CASE("parallel: the thread count") {
  CHECK(ResolveThreadCount(3) == 3);
  CHECK(ResolveThreadCount(0) >= 1);
  CHECK(ResolveThreadCount(-2) >= 1);
}

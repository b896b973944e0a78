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

namespace {
std::atomic<int> g_thread_starts{0};
struct ThreadStart {
  ThreadStart() { ++g_thread_starts; }
};
thread_local ThreadStart t_start;
}  // namespace

TEST_CASE("parallel: the workers persist from call to call") {
  // Each thread that runs a chunk constructs its thread_local once. A thread per call would
  // construct 3 more per call (150 here); the pool's workers construct theirs once, so at most
  // as many as the largest pool any test of this binary asks for (16 threads).
  std::atomic<long> sum{0};
  const int before = g_thread_starts.load();
  for (int call = 0; call < 50; ++call) {
    ParallelFor(4, 400, [&](std::size_t b, std::size_t e) {
      (void)&t_start;
      for (std::size_t i = b; i < e; ++i) sum += static_cast<long>(i);
    });
  }
  CHECK(sum.load() == 50L * (399L * 400L / 2));
  CHECK(g_thread_starts.load() - before <= 16);
}

TEST_CASE("parallel: a chunk may run a parallel loop itself") {
  std::vector<std::atomic<int>> hits(8 * 10);
  for (auto& h : hits) h = 0;
  ParallelFor(4, 8, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      ParallelFor(3, 10, [&](std::size_t ib, std::size_t ie) {
        for (std::size_t j = ib; j < ie; ++j) ++hits[10 * i + j];
      });
    }
  });
  for (const auto& h : hits) CHECK(h.load() == 1);
}

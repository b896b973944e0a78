// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief A minimal deterministic parallel loop (offline tools, plan precomputation).
#pragma once

#include <cstddef>
#include <functional>

namespace dermis {

/// The number of threads to use: `requested` if > 0, else the hardware concurrency (>= 1).
int ResolveThreadCount(int requested);

/// Calls fn(begin, end) on `threads` contiguous, disjoint chunks that cover [0, count), on the
/// calling thread and the workers of a persistent process-wide pool (started on first use,
/// grown to the largest `threads` asked for; no thread is created per call). The split depends
/// only on `count` and `threads`; callers write results per index, so the output never depends
/// on scheduling. fn may call ParallelFor itself. Returns when every chunk has run.
void ParallelFor(int threads, std::size_t count,
                 const std::function<void(std::size_t begin, std::size_t end)>& fn);

}  // namespace dermis

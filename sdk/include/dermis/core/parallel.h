// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief A minimal deterministic parallel loop for the offline tools.
#pragma once

#include <cstddef>
#include <functional>

namespace dermis {

/// The number of threads to use: `requested` if > 0, else the hardware concurrency (>= 1).
int ResolveThreadCount(int requested);

/// Calls fn(begin, end) on `threads` contiguous, disjoint chunks that cover [0, count), one
/// chunk per std::thread (the calling thread takes the first). The split depends only on
/// `count` and `threads`; callers write results per index, so the output never depends on
/// scheduling.
void ParallelFor(int threads, std::size_t count,
                 const std::function<void(std::size_t begin, std::size_t end)>& fn);

}  // namespace dermis

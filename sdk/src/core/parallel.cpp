// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Static-partition parallel loop on a persistent pool of worker threads (std::thread; no TBB
// needed for these coarse loops). No thread is created per call: the pool starts its workers on
// first use and grows to the largest thread count asked for (docs/performance.md, "Threads").
//
// A call splits [0, count) into n fixed chunks (the split depends only on count and n, so
// results never depend on scheduling), queues a job, runs chunk 0 on the calling thread, then
// claims and runs every chunk no worker has claimed yet, and finally waits only for the chunks
// workers are running. The caller never waits for a chunk nobody runs, so a chunk may itself
// call ParallelFor (nested loops cannot deadlock) and the pool's size only changes the speed.
#include "dermis/core/parallel.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace dermis {
namespace {

struct Job {
  const std::function<void(std::size_t, std::size_t)>* fn = nullptr;
  std::size_t count = 0;
  std::size_t chunks = 0;
  std::atomic<std::size_t> next{1};  // the next chunk to claim; chunk 0 is the caller's
  // Under the pool's mutex: chunks workers claimed, and how many of those they finished.
  std::size_t claimed = 0;
  std::size_t finished = 0;
  std::condition_variable done;

  void Run(std::size_t c) const { (*fn)(count * c / chunks, count * (c + 1) / chunks); }
};

class Pool {
 public:
  // Makes sure at least `workers` worker threads exist.
  void Reserve(std::size_t workers) {
    std::lock_guard<std::mutex> lock(mutex_);
    while (threads_.size() < workers) threads_.emplace_back([this] { WorkerLoop(); });
  }

  void Run(const std::shared_ptr<Job>& job) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.push_back(job);
    }
    work_.notify_all();
    job->Run(0);
    for (std::size_t c = job->next.fetch_add(1); c < job->chunks; c = job->next.fetch_add(1))
      job->Run(c);
    // Every chunk is claimed now; a worker's claim and its count happen under the mutex, so
    // job->claimed is final once we hold it.
    std::unique_lock<std::mutex> lock(mutex_);
    Forget(job);
    job->done.wait(lock, [&] { return job->finished == job->claimed; });
  }

 private:
  void Forget(const std::shared_ptr<Job>& job) {
    queue_.erase(std::remove(queue_.begin(), queue_.end(), job), queue_.end());
  }

  void WorkerLoop() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      work_.wait(lock, [&] { return !queue_.empty(); });
      const std::shared_ptr<Job> job = queue_.front();
      const std::size_t c = job->next.fetch_add(1);
      if (c >= job->chunks) {
        Forget(job);
        continue;
      }
      ++job->claimed;
      lock.unlock();
      job->Run(c);
      lock.lock();
      if (++job->finished == job->claimed) job->done.notify_all();
    }
  }

  std::mutex mutex_;
  std::condition_variable work_;
  std::deque<std::shared_ptr<Job>> queue_;
  std::vector<std::thread> threads_;
};

// The process's pool. Never destroyed: its workers wait for work until the process exits
// (joining them from a static destructor could race with other static destructors).
Pool& ThePool() {
  static Pool* pool = new Pool();
  return *pool;
}

}  // namespace

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
  Pool& pool = ThePool();
  pool.Reserve(n - 1);
  auto job = std::make_shared<Job>();
  job->fn = &fn;
  job->count = count;
  job->chunks = n;
  pool.Run(job);
}

}  // namespace dermis

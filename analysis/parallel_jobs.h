#pragma once
// Runs independent jobs 0..count-1 on worker threads. Each job writes only its own result slot,
// and every random draw inside a job is keyed by the job (CounterRandom seeded per fit), so the
// results are identical for any thread count, including 1.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace glarelab::analysis {

// Threads to use for `requested` (0: one per hardware thread), never more than the jobs.
inline unsigned worker_threads(unsigned requested, std::size_t jobs) {
  unsigned threads = requested != 0 ? requested : std::max(1u, std::thread::hardware_concurrency());
  return static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(jobs, 1)));
}

// Calls job(i) for every i in [0, count) on `threads` threads (0: hardware threads). The first
// exception a job throws is rethrown here after all threads have stopped.
template <typename Job>
void run_parallel_jobs(std::size_t count, unsigned threads, Job&& job) {
  const unsigned workers = worker_threads(threads, count);
  if (workers <= 1) {
    for (std::size_t i = 0; i < count; ++i) job(i);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto work = [&]() {
    for (std::size_t i = next++; i < count; i = next++) {
      try {
        job(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        next = count;  // stop handing out jobs
      }
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(workers - 1);
  for (unsigned t = 1; t < workers; ++t) pool.emplace_back(work);
  work();
  for (std::thread& thread : pool) thread.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace glarelab::analysis

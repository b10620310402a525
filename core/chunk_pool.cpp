#include "core/chunk_pool.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

namespace glarelab {
namespace {

// One run_chunks call: its chunks are claimed by index, by the caller and by any worker.
struct ChunkJob {
  const std::function<void(int)>* run_chunk = nullptr;
  int chunks = 0;
  std::atomic<int> next{0};
  int finished = 0;  // under done_mutex
  std::exception_ptr error;
  std::mutex done_mutex;
  std::condition_variable done;

  // Runs chunks until none is left to claim.
  void work() {
    for (int chunk = next.fetch_add(1); chunk < chunks; chunk = next.fetch_add(1)) {
      std::exception_ptr thrown;
      try {
        (*run_chunk)(chunk);
      } catch (...) {
        thrown = std::current_exception();
      }
      std::lock_guard lock(done_mutex);
      if (thrown && !error) error = thrown;
      if (++finished == chunks) done.notify_all();
    }
  }
};

class ChunkPool {
 public:
  void run(int chunks, const std::function<void(int)>& run_chunk) {
    auto job = std::make_shared<ChunkJob>();
    job->run_chunk = &run_chunk;
    job->chunks = chunks;
    {
      std::lock_guard lock(mutex_);
      // Enough workers for this call's other chunks (never more than kMaxChunkWorkers).
      for (const int wanted = std::min(kMaxChunkWorkers, chunks - 1); workers_ < wanted; ++workers_)
        std::thread([this] { serve(); }).detach();
      jobs_.push_back(job);
    }
    wake_.notify_all();
    job->work();
    std::unique_lock lock(job->done_mutex);
    job->done.wait(lock, [&] { return job->finished == job->chunks; });
    if (job->error) std::rethrow_exception(job->error);
  }

  int started() {
    std::lock_guard lock(mutex_);
    return workers_;
  }

 private:
  void serve() {
    for (;;) {
      std::shared_ptr<ChunkJob> job;
      {
        std::unique_lock lock(mutex_);
        wake_.wait(lock, [&] { return !jobs_.empty(); });
        job = jobs_.front();
        // A job whose chunks are all claimed leaves the queue; its caller waits for the last ones.
        if (job->next.load() >= job->chunks) {
          jobs_.pop_front();
          continue;
        }
      }
      job->work();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::shared_ptr<ChunkJob>> jobs_;
  int workers_ = 0;  // started, detached
};

// Never destroyed: its detached workers wait on it until the process ends, and no static
// destructor has to stop them while another static's destructor may still use a loop.
ChunkPool& pool() {
  static ChunkPool* instance = new ChunkPool;
  return *instance;
}

}  // namespace

void run_chunks(int chunks, const std::function<void(int chunk)>& run_chunk) {
  if (chunks <= 0) return;
  if (chunks == 1) {
    run_chunk(0);
    return;
  }
  pool().run(chunks, run_chunk);
}

int chunk_workers_started() { return pool().started(); }

}  // namespace glarelab

#include "core/chunk_pool.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
#include <map>
#include <mutex>
#include <thread>

#ifdef __linux__
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

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
  explicit ChunkPool(int niceness) : niceness_(niceness) {}

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
#ifdef __linux__
    // Inherited from the caller that started it already; said again in case a platform does not.
    setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), niceness_);  // best effort
#endif
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
  int niceness_;
};

// The calling thread's niceness (Linux keeps one per thread; 0 elsewhere).
int caller_niceness() {
#ifdef __linux__
  return getpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)));
#else
  return 0;
#endif
}

// One pool per niceness of the threads that call it. A thread started by a caller inherits the
// caller's niceness, so a pool's workers run at its callers' priority: the chunks of a thread
// working below the display's (the session's worker preparing the next trial at a niceness of 5,
// runner/session/trial_ahead.cpp) never run on workers at the display thread's priority, and
// never wait behind its chunks. (An unprivileged thread cannot lower its niceness again, so one
// pool whose workers changed priority per job would be stuck at the highest niceness it met.)
// Never destroyed: their detached workers wait on them until the process ends, and no static
// destructor has to stop them while another static's destructor may still use a loop.
ChunkPool& pool() {
  static std::mutex mutex;
  static auto* pools = new std::map<int, ChunkPool*>;
  const int niceness = caller_niceness();
  std::lock_guard lock(mutex);
  ChunkPool*& instance = (*pools)[niceness];
  if (instance == nullptr) instance = new ChunkPool(niceness);
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

int chunk_thread_niceness() { return caller_niceness(); }

}  // namespace glarelab

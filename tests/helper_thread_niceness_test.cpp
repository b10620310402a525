// The frame engine's helper threads below the flips' priority (docs/TIMING.md, "Trials prepared
// ahead"): the chunks of core's parallel loop, and FFTW's parallel transforms (which run on the same
// pool, glare/cpu/fftw_float_plan.cpp), run at the niceness of the thread that asked for them. The
// session's worker preparing the next trial runs at a niceness of 5: its helpers must not run at the
// display thread's. Asserted from each thread's own niceness as the kernel reports it, never from
// timing.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <chrono>
#include <complex>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

#include "core/chunk_pool.h"
#include "glare/cpu/fftw_float_plan.h"

namespace glarelab {
namespace {

void set_own_niceness(int niceness) {
  ASSERT_EQ(setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), niceness), 0);
}

struct ChunkThreads {
  std::set<int> niceness;
  std::set<std::thread::id> threads;
};

// Eight chunks of 5 ms each from a thread at `niceness`: what each chunk's thread reported.
ChunkThreads chunks_at(int niceness) {
  ChunkThreads seen;
  std::thread([&] {
    set_own_niceness(niceness);
    std::mutex mutex;
    run_chunks(8, [&](int) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));  // long enough for the workers to take some
      const std::lock_guard lock(mutex);
      seen.niceness.insert(chunk_thread_niceness());
      seen.threads.insert(std::this_thread::get_id());
    });
  }).join();
  return seen;
}

TEST(HelperThreadNiceness, ChunksRunAtTheirCallersNiceness) {
  const int base = chunk_thread_niceness();
  if (base > 12) GTEST_SKIP() << "the tests run at niceness " << base << ": no room below";
  // The normal caller first, so that its workers exist when the lower-priority caller comes (with
  // one pool, those workers would run its chunks at the normal niceness), then the normal one again.
  for (const int raise : {0, 5, 0, 7}) {
    const ChunkThreads seen = chunks_at(base + raise);
    EXPECT_GT(seen.threads.size(), 1u) << "the pool's workers took chunks";
    EXPECT_EQ(seen.niceness, std::set<int>{base + raise}) << "caller at niceness " << base + raise;
  }
}

TEST(HelperThreadNiceness, FftwsThreadedTransformsRunOnThePoolAtTheCallersNiceness) {
  const int base = chunk_thread_niceness();
  if (base > 10) GTEST_SKIP() << "the tests run at niceness " << base << ": no room below";
  // A niceness no other test calls from: its pool starts with no worker, and only FFTW's jobs,
  // handed to the pool (fftwf_threads_set_callback), can start some.
  const int niceness = base + 9;
  int workers_before = -1, workers_after = -1;
  std::thread([&] {
    set_own_niceness(niceness);
    workers_before = chunk_workers_started();
    const int rows = 256, cols = 256;
    FftwFloatBuffer<std::complex<float>> in(rows * cols), out(rows * cols);
    const FftwFloatPlan plan = FftwFloatPlan::complex_forward(rows, cols, in.data(), out.data(), 2);
    for (int k = 0; k < rows * cols; ++k) in.data()[k] = {static_cast<float>(k % 7), 0.0f};
    plan.execute();
    workers_after = chunk_workers_started();
    // The transform is still the DFT: bin 0 is the sum of the inputs.
    double sum = 0.0;
    for (int k = 0; k < rows * cols; ++k) sum += k % 7;
    EXPECT_NEAR(out.data()[0].real(), sum, 1e-6 * sum);
  }).join();
  EXPECT_EQ(workers_before, 0);
  EXPECT_GT(workers_after, 0) << "FFTW's threads are the pool's, started by a caller at niceness " << niceness;
}

}  // namespace
}  // namespace glarelab

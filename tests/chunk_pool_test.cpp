// The worker pool behind parallel_chunks (core/chunk_pool.h): every chunk runs once, the chunks
// are the serial loop's, nested and concurrent calls finish, a chunk's exception reaches the
// caller, and the workers are started once, not per call.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/chunk_pool.h"
#include "core/parallel_for.h"

namespace glarelab {
namespace {

TEST(ChunkPool, EveryIndexIsVisitedOnceInTheSerialLoopsChunks) {
  for (const int count : {0, 1, 2, 3, 7, 100, 1001})
    for (const int threads : {1, 2, 3, 8}) {
      std::vector<int> visits(static_cast<std::size_t>(count), 0);
      std::vector<std::pair<int, int>> chunks(static_cast<std::size_t>(threads), {-1, -1});
      std::atomic<int> calls{0};
      parallel_chunks(count, threads, [&](int first, int last) {
        const int call = calls.fetch_add(1);
        chunks[static_cast<std::size_t>(call)] = {first, last};
        for (int k = first; k < last; ++k) ++visits[static_cast<std::size_t>(k)];
      });
      for (int k = 0; k < count; ++k) ASSERT_EQ(visits[static_cast<std::size_t>(k)], 1) << count << " " << threads;
      // The chunks are [count c / n, count (c + 1) / n) for n = min(threads, count) chunks.
      const int expected_chunks = count == 0 ? 0 : std::min(threads, count);
      ASSERT_EQ(calls.load(), expected_chunks) << count << " " << threads;
      std::vector<int> firsts;
      for (int c = 0; c < expected_chunks; ++c) firsts.push_back(chunks[static_cast<std::size_t>(c)].first);
      std::sort(firsts.begin(), firsts.end());
      for (int c = 0; c < expected_chunks; ++c)
        EXPECT_EQ(firsts[static_cast<std::size_t>(c)], static_cast<int>(static_cast<long long>(count) * c / expected_chunks));
    }
}

TEST(ChunkPool, NestedAndConcurrentCallsFinish) {
  // Four callers at once, each with chunks that start loops of their own: more chunks in flight
  // than there are workers, so callers must run chunks themselves.
  std::vector<std::thread> callers;
  std::vector<long long> sums(4, 0);
  for (int t = 0; t < 4; ++t)
    callers.emplace_back([&, t] {
      for (int round = 0; round < 50; ++round) {
        std::atomic<long long> sum{0};
        parallel_chunks(6, 3, [&](int first, int last) {
          for (int outer = first; outer < last; ++outer)
            parallel_chunks(10, 2, [&](int inner_first, int inner_last) {
              for (int inner = inner_first; inner < inner_last; ++inner) sum += outer * 10 + inner;
            });
        });
        sums[static_cast<std::size_t>(t)] += sum.load();
      }
    });
  for (std::thread& caller : callers) caller.join();
  // sum over 0..59 = 1770, 50 rounds.
  for (const long long sum : sums) EXPECT_EQ(sum, 50 * 1770);
}

TEST(ChunkPool, AChunksExceptionReachesTheCallerAfterEveryChunkRan) {
  std::atomic<int> ran{0};
  EXPECT_THROW(run_chunks(5,
                          [&](int chunk) {
                            ++ran;
                            if (chunk == 2) throw std::runtime_error("chunk 2 failed");
                          }),
               std::runtime_error);
  EXPECT_EQ(ran.load(), 5);
  // The pool still works afterwards.
  std::atomic<int> after{0};
  run_chunks(4, [&](int) { ++after; });
  EXPECT_EQ(after.load(), 4);
}

TEST(ChunkPool, WorkersAreStartedOnceNotPerCall) {
  for (int call = 0; call < 200; ++call) parallel_chunks(64, 3, [](int, int) {});
  const int started = chunk_workers_started();
  EXPECT_GE(started, 2);
  EXPECT_LE(started, kMaxChunkWorkers);
  for (int call = 0; call < 200; ++call) parallel_chunks(64, 3, [](int, int) {});
  EXPECT_EQ(chunk_workers_started(), started);
}

}  // namespace
}  // namespace glarelab

#pragma once
// The one parallel loop of the tree. Splits a loop over rows (or any index range) into contiguous
// chunks, one per thread. Each chunk does exactly the work the serial loop would do for its
// indices, in the same order, so the result does not depend on the thread count, nor on which
// thread ran a chunk, whenever the rows are independent (rasterising, power spectra, the spectral
// PSF's output rows, one psychometric fit per job).
//
// The chunks run on a pool of worker threads started once per process (chunk_pool.h), with the
// caller taking chunks too: a glare frame makes a dozen such calls, too many to start threads for
// each (docs/PERFORMANCE.md, "Worker threads started once").
#include <algorithm>
#include <cstddef>
#include <thread>

#include "core/chunk_pool.h"

namespace glarelab {

// body(chunk, first, last) for [first, last) chunks covering [0, count), chunk their index in
// [0, max(1, threads)): each chunk may use buffers of its own, one per thread, indexed by it;
// threads <= 1 runs it inline. An exception from a chunk is rethrown here once every chunk has finished.
template <typename Body>
void parallel_indexed_chunks(int count, int threads, Body&& body) {
  const int chunks = std::clamp(threads, 1, std::max(1, count));
  if (chunks <= 1) {
    if (count > 0) body(0, 0, count);
    return;
  }
  const auto bound = [&](int chunk) { return static_cast<int>(static_cast<long long>(count) * chunk / chunks); };
  run_chunks(chunks, [&](int chunk) { body(chunk, bound(chunk), bound(chunk + 1)); });
}

// body(first, last) for [first, last) chunks covering [0, count), as parallel_indexed_chunks.
template <typename Body>
void parallel_chunks(int count, int threads, Body&& body) {
  parallel_indexed_chunks(count, threads, [&](int, int first, int last) { body(first, last); });
}

// `requested` threads, or one per hardware thread for 0 (at least 1).
inline unsigned resolved_threads(unsigned requested) {
  return requested != 0 ? requested : std::max(1u, std::thread::hardware_concurrency());
}

// job(i) for every i in [0, count) in the chunks of parallel_chunks, on resolved_threads(threads)
// threads (at most kMaxChunkWorkers + 1 run at once): for independent jobs that each write only
// their own result (the analysis' fits, each seeded by its job), whose results are then the same
// for any thread count. A job's exception ends its chunk and is rethrown as parallel_chunks does.
template <typename Job>
void parallel_for(std::size_t count, unsigned threads, Job&& job) {
  const auto chunks =
      static_cast<int>(std::min<std::size_t>(resolved_threads(threads), std::max<std::size_t>(count, 1)));
  parallel_chunks(static_cast<int>(count), chunks, [&](int first, int last) {
    for (int i = first; i < last; ++i) job(static_cast<std::size_t>(i));
  });
}

}  // namespace glarelab

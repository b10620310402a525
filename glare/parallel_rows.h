#pragma once
// Splits a loop over rows (or any index range) into contiguous chunks, one per thread. Each chunk
// does exactly the work the serial loop would do for its indices, in the same order, so the result
// does not depend on the thread count, nor on which thread ran a chunk, whenever the rows are
// independent (rasterising, power spectra, the spectral PSF's output rows).
//
// The chunks run on a pool of worker threads started once per process (chunk_pool.h), with the
// caller taking chunks too: a glare frame makes a dozen such calls, and starting threads for each
// would cost a fixed time per call (docs/PERFORMANCE.md, "Measurements behind the code's choices").
#include <algorithm>

#include "glare/chunk_pool.h"

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

}  // namespace glarelab

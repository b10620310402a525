#pragma once
// Splits a loop over rows (or any index range) into contiguous chunks, one per thread, the caller
// running the last one. Each chunk does exactly the work the serial loop would do for its indices,
// in the same order, so the result does not depend on the thread count whenever the rows are
// independent (rasterising, power spectra, the spectral PSF's output rows).
#include <algorithm>
#include <thread>
#include <vector>

namespace glarelab {

// body(first, last) for [first, last) chunks covering [0, count); threads <= 1 runs it inline.
template <typename Body>
void parallel_chunks(int count, int threads, Body&& body) {
  const int chunks = std::clamp(threads, 1, std::max(1, count));
  if (chunks <= 1) {
    if (count > 0) body(0, count);
    return;
  }
  std::vector<std::thread> workers;
  workers.reserve(static_cast<std::size_t>(chunks - 1));
  const auto bound = [&](int chunk) { return static_cast<int>(static_cast<long long>(count) * chunk / chunks); };
  for (int chunk = 0; chunk + 1 < chunks; ++chunk)
    workers.emplace_back([&body, first = bound(chunk), last = bound(chunk + 1)] { body(first, last); });
  body(bound(chunks - 1), count);
  for (std::thread& worker : workers) worker.join();
}

}  // namespace glarelab

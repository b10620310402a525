#include "stimuli/luminance_range.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

#include "core/parallel_for.h"

namespace glarelab {

// Rows on threads (min and max do not depend on the order).
std::pair<double, double> luminance_range(const ImageRGBA& image) {
  if (image.empty()) return {0.0, 0.0};
  constexpr int kChunks = 2;
  double lowest[kChunks], highest[kChunks];
  std::fill(std::begin(lowest), std::end(lowest), std::numeric_limits<double>::infinity());
  std::fill(std::begin(highest), std::end(highest), -std::numeric_limits<double>::infinity());
  const auto pixels = static_cast<int>(image.rgba.size() / 4);
  parallel_chunks(kChunks, kChunks, [&](int first, int last) {
    for (int chunk = first; chunk < last; ++chunk) {
      const std::size_t begin = static_cast<std::size_t>(pixels) * chunk / kChunks;
      const std::size_t end = static_cast<std::size_t>(pixels) * (chunk + 1) / kChunks;
      double low = std::numeric_limits<double>::infinity(), high = -std::numeric_limits<double>::infinity();
      for (std::size_t k = begin; k < end; ++k) {
        const float* p = &image.rgba[4 * k];
        const double y = luminance_rec709(p[0], p[1], p[2]);
        low = std::min(low, y);
        high = std::max(high, y);
      }
      lowest[chunk] = low;
      highest[chunk] = high;
    }
  });
  const double high = std::max(highest[0], highest[1]);
  return {std::min(lowest[0], lowest[1]), std::isinf(high) ? 0.0 : high};  // no pixel but NaN: 0, as max_luminance
}

}  // namespace glarelab

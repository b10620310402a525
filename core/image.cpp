#include "core/image.h"

#include <cmath>
#include <cstddef>
#include <iterator>
#include <limits>
#include <stdexcept>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace glarelab {
namespace {

// The values of a new image in order, `fill` in the colour channels and 1 in alpha: a forward
// iterator, so that std::vector's range constructor knows the count and writes each value once.
struct NewPixelValues {
  using iterator_category = std::forward_iterator_tag;
  using value_type = float;
  using difference_type = std::ptrdiff_t;
  using pointer = const float*;
  using reference = float;
  std::size_t index = 0;
  float fill = 0.0f;
  float operator*() const { return (index & 3) == 3 ? 1.0f : fill; }
  NewPixelValues& operator++() {
    ++index;
    return *this;
  }
  NewPixelValues operator++(int) {
    NewPixelValues before = *this;
    ++index;
    return before;
  }
  bool operator==(const NewPixelValues& other) const { return index == other.index; }
};

}  // namespace

// Colour channels take `fill`; alpha is 1 so that a new image is opaque, as an EXR without an
// alpha channel reads.
ImageRGBA::ImageRGBA(int width, int height, float fill) : width_px(width), height_px(height) {
  if (width < 0 || height < 0) {
    throw std::invalid_argument("ImageRGBA: negative size " + std::to_string(width) + "x" + std::to_string(height));
  }
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  // Made from the values in order, so the vector is allocated and written once (resizing would zero
  // it and then the loop write it again): 20 to 25 % less time for a frame-sized image, most of
  // the rest the fresh pages' faults (docs/PERFORMANCE.md, 2026-12-01).
  rgba = std::vector<float>(NewPixelValues{0, fill}, NewPixelValues{4 * pixels, fill});
}

namespace {

// Whether every R, G and B value lies in [0, FLT_MAX] (-0 included: it is not negative), the
// common case answered in one vector pass before the counting one: ordered comparisons, false for a
// NaN, with the alpha lane taken as passing.
bool colour_channels_in_range(const float* rgba, std::size_t pixels) {
#if defined(__x86_64__) && defined(__GNUC__)
  const __m128 zero = _mm_setzero_ps(), largest = _mm_set1_ps(std::numeric_limits<float>::max());
  const __m128 alpha_lane = _mm_castsi128_ps(_mm_set_epi32(-1, 0, 0, 0));
  __m128 ok = _mm_castsi128_ps(_mm_set1_epi32(-1));
  for (std::size_t i = 0; i < pixels; ++i) {
    const __m128 v = _mm_loadu_ps(rgba + 4 * i);
    ok = _mm_and_ps(ok, _mm_or_ps(alpha_lane, _mm_and_ps(_mm_cmpge_ps(v, zero), _mm_cmple_ps(v, largest))));
  }
  return _mm_movemask_ps(ok) == 0xF;
#else
  for (std::size_t i = 0; i < pixels; ++i)
    for (int c = 0; c < 3; ++c)
      if (!(rgba[4 * i + c] >= 0.0f && rgba[4 * i + c] <= std::numeric_limits<float>::max())) return false;
  return true;
#endif
}

std::string count_phrase(std::size_t count, const char* what) {
  return std::to_string(count) + " " + what + (count == 1 ? " pixel" : " pixels");
}

}  // namespace

std::string NonFiniteReport::describe() const {
  if (clean()) return "no NaN, Inf or negative pixels";
  std::string text;
  const auto append = [&text](std::size_t count, const char* what) {
    if (count == 0) return;
    if (!text.empty()) text += ", ";
    text += count_phrase(count, what);
  };
  append(nan_pixels, "NaN");
  append(inf_pixels, "Inf");
  append(negative_pixels, "negative");
  return text;
}

// Only R, G and B are inspected: alpha is not a luminance. A pixel is counted once per kind of
// problem it has, so one pixel can appear in several counts (-Inf is both Inf and negative).
NonFiniteReport inspect_pixels(const ImageRGBA& image) {
  NonFiniteReport report;
  const std::size_t pixels = image.rgba.size() / 4;
  if (colour_channels_in_range(image.rgba.data(), pixels)) return report;
  for (std::size_t i = 0; i < pixels; ++i) {
    const float* p = &image.rgba[4 * i];
    bool nan = false;
    bool inf = false;
    bool negative = false;
    for (int c = 0; c < 3; ++c) {
      nan = nan || std::isnan(p[c]);
      inf = inf || std::isinf(p[c]);
      negative = negative || p[c] < 0.0f;
    }
    report.nan_pixels += nan ? 1 : 0;
    report.inf_pixels += inf ? 1 : 0;
    report.negative_pixels += negative ? 1 : 0;
  }
  return report;
}

// Pixels whose luminance is NaN have no place in an ordering or a sum and are skipped;
// inspect_pixels reports them. Both functions return 0 for an image with no such pixels.
double max_luminance(const ImageRGBA& image) {
  double result = -std::numeric_limits<double>::infinity();
  bool any = false;
  const std::size_t pixels = image.rgba.size() / 4;
  for (std::size_t i = 0; i < pixels; ++i) {
    const float* p = &image.rgba[4 * i];
    const double y = luminance_rec709(p[0], p[1], p[2]);
    if (std::isnan(y)) continue;
    any = true;
    if (y > result) result = y;
  }
  return any ? result : 0.0;
}

double mean_luminance(const ImageRGBA& image) {
  double sum = 0.0;
  std::size_t count = 0;
  const std::size_t pixels = image.rgba.size() / 4;
  for (std::size_t i = 0; i < pixels; ++i) {
    const float* p = &image.rgba[4 * i];
    const double y = luminance_rec709(p[0], p[1], p[2]);
    if (std::isnan(y)) continue;
    sum += y;
    ++count;
  }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

}  // namespace glarelab

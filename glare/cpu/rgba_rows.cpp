#include "glare/cpu/rgba_rows.h"

#include <limits>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace glarelab {

namespace {

// >= 0 and <= the largest float: false for NaN (both comparisons fail), infinities and negatives.
bool valid(float value) { return (value >= 0.0f) & (value <= std::numeric_limits<float>::max()); }

}  // namespace

bool split_rgba_row(const float* rgba, int width, float* red, float* green, float* blue, float* alpha) {
  int x = 0;
  bool clean = true;
#if defined(__SSE__)
  const __m128 zero = _mm_setzero_ps(), largest = _mm_set1_ps(std::numeric_limits<float>::max());
  // Ordered comparisons, as the scalar ones: a NaN lane is false in both.
  const auto in_range = [&](__m128 v) { return _mm_and_ps(_mm_cmpge_ps(v, zero), _mm_cmple_ps(v, largest)); };
  __m128 all_valid = _mm_cmpeq_ps(zero, zero);  // every bit set
  for (; x + 4 <= width; x += 4) {
    __m128 r = _mm_loadu_ps(rgba + 4 * x), g = _mm_loadu_ps(rgba + 4 * x + 4);
    __m128 b = _mm_loadu_ps(rgba + 4 * x + 8), a = _mm_loadu_ps(rgba + 4 * x + 12);
    _MM_TRANSPOSE4_PS(r, g, b, a);  // four pixels' R, G, B, A
    all_valid = _mm_and_ps(all_valid, _mm_and_ps(in_range(r), _mm_and_ps(in_range(g), in_range(b))));
    _mm_storeu_ps(red + x, r);
    _mm_storeu_ps(green + x, g);
    _mm_storeu_ps(blue + x, b);
    if (alpha) _mm_storeu_ps(alpha + x, a);
  }
  clean = _mm_movemask_ps(all_valid) == 0xF;
#endif
  for (; x < width; ++x) {
    const float* p = rgba + 4 * x;
    clean &= valid(p[0]) & valid(p[1]) & valid(p[2]);
    red[x] = p[0];
    green[x] = p[1];
    blue[x] = p[2];
    if (alpha) alpha[x] = p[3];
  }
  return clean;
}

void join_rgba_row(const float* red, const float* green, const float* blue, const float* alpha, int width, float* rgba) {
  int x = 0;
#if defined(__SSE__)
  for (; x + 4 <= width; x += 4) {
    __m128 p0 = _mm_loadu_ps(red + x), p1 = _mm_loadu_ps(green + x);
    __m128 p2 = _mm_loadu_ps(blue + x), p3 = _mm_loadu_ps(alpha + x);
    _MM_TRANSPOSE4_PS(p0, p1, p2, p3);  // four pixels, each R, G, B, A
    _mm_storeu_ps(rgba + 4 * x, p0);
    _mm_storeu_ps(rgba + 4 * x + 4, p1);
    _mm_storeu_ps(rgba + 4 * x + 8, p2);
    _mm_storeu_ps(rgba + 4 * x + 12, p3);
  }
#endif
  for (; x < width; ++x) {
    float* p = rgba + 4 * x;
    p[0] = red[x];
    p[1] = green[x];
    p[2] = blue[x];
    p[3] = alpha[x];
  }
}

}  // namespace glarelab

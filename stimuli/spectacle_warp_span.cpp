#include "stimuli/spectacle_warp_span.h"

#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "stimuli/float4.h"

namespace glarelab {
namespace {

#if defined(__SSE2__)
void warp_clear_span_sse2(const float* scene, std::ptrdiff_t row_floats, const WarpCellLine line[3], const double* fraction,
                          int first, int last, float* out_row) {
  __m128d edge[3], step[3];
  for (int c = 0; c < 3; ++c) {
    edge[c] = _mm_set_pd(line[c].edge_y, line[c].edge_x);
    step[c] = _mm_set_pd(line[c].step_y, line[c].step_x);
  }
  const __m128d one = _mm_set1_pd(1.0);
  const __m128 red = _mm_castsi128_ps(_mm_set_epi32(0, 0, 0, -1)), blue = _mm_castsi128_ps(_mm_set_epi32(0, -1, 0, 0));
  const auto sample = [&](int c, __m128d f) {
    const __m128d at = _mm_add_pd(edge[c], _mm_mul_pd(f, step[c]));
    const __m128i cell = _mm_cvttpd_epi32(at);  // the truncation is the floor: positions are >= 0
    const __m128d frac = _mm_sub_pd(at, _mm_cvtepi32_pd(cell));
    const __m128 w1 = _mm_cvtpd_ps(frac), w0 = _mm_cvtpd_ps(_mm_sub_pd(one, frac));  // (wx, wy, 0, 0)
    const std::ptrdiff_t x0 = _mm_cvtsi128_si32(cell), y0 = _mm_cvtsi128_si32(_mm_shuffle_epi32(cell, 1));
    const float* corner = scene + y0 * row_floats + 4 * x0;
    const __m128 wx0 = _mm_shuffle_ps(w0, w0, 0x00), wx1 = _mm_shuffle_ps(w1, w1, 0x00);
    const __m128 wy0 = _mm_shuffle_ps(w0, w0, 0x55), wy1 = _mm_shuffle_ps(w1, w1, 0x55);
    const __m128 top = _mm_add_ps(_mm_mul_ps(wx0, _mm_loadu_ps(corner)), _mm_mul_ps(wx1, _mm_loadu_ps(corner + 4)));
    const __m128 bottom = _mm_add_ps(_mm_mul_ps(wx0, _mm_loadu_ps(corner + row_floats)),
                                     _mm_mul_ps(wx1, _mm_loadu_ps(corner + row_floats + 4)));
    return _mm_add_ps(_mm_mul_ps(wy0, top), _mm_mul_ps(wy1, bottom));
  };
  for (int x = first; x < last; ++x) {
    const __m128d f = _mm_set1_pd(fraction[x]);
    const __m128 r = sample(0, f), g = sample(1, f), b = sample(2, f);
    const __m128 rg = _mm_or_ps(_mm_and_ps(red, r), _mm_andnot_ps(red, g));
    _mm_storeu_ps(out_row + 4 * static_cast<std::ptrdiff_t>(x), _mm_or_ps(_mm_and_ps(blue, b), _mm_andnot_ps(blue, rg)));
  }
}
#else
// Elsewhere: Float4's scalar lanes, the same operations.
void warp_clear_span_sse2(const float* scene, std::ptrdiff_t row_floats, const WarpCellLine line[3], const double* fraction,
                          int first, int last, float* out_row) {
  for (int x = first; x < last; ++x) {
    Float4 seen[3];
    for (int c = 0; c < 3; ++c) {
      const double ax = line[c].edge_x + fraction[x] * line[c].step_x, ay = line[c].edge_y + fraction[x] * line[c].step_y;
      const auto x0 = static_cast<std::ptrdiff_t>(ax), y0 = static_cast<std::ptrdiff_t>(ay);
      const double fx = ax - static_cast<double>(x0), fy = ay - static_cast<double>(y0);
      const Float4 wx0 = Float4::all(static_cast<float>(1.0 - fx)), wx1 = Float4::all(static_cast<float>(fx));
      const Float4 wy0 = Float4::all(static_cast<float>(1.0 - fy)), wy1 = Float4::all(static_cast<float>(fy));
      const float* corner = scene + y0 * row_floats + 4 * x0;
      const Float4 top = wx0 * Float4::load(corner) + wx1 * Float4::load(corner + 4);
      const Float4 bottom = wx0 * Float4::load(corner + row_floats) + wx1 * Float4::load(corner + row_floats + 4);
      seen[c] = wy0 * top + wy1 * bottom;
    }
    const Mask4 red = Mask4::of(true, false, false, false), blue = Mask4::of(false, false, true, false);
    select(red, seen[0], select(blue, seen[2], seen[1])).store(out_row + 4 * static_cast<std::ptrdiff_t>(x));
  }
}
#endif

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2,fma"))) void warp_clear_span_avx2(const float* scene, int row_floats, const WarpCellLine line[3],
                                                               const double* fraction, int first, int last, float* out_row) {
  // Lanes R, G, B, G: the fourth lane repeats green, whose position alpha takes too.
  const __m256d edge_x = _mm256_setr_pd(line[0].edge_x, line[1].edge_x, line[2].edge_x, line[1].edge_x);
  const __m256d edge_y = _mm256_setr_pd(line[0].edge_y, line[1].edge_y, line[2].edge_y, line[1].edge_y);
  const __m256d step_x = _mm256_setr_pd(line[0].step_x, line[1].step_x, line[2].step_x, line[1].step_x);
  const __m256d step_y = _mm256_setr_pd(line[0].step_y, line[1].step_y, line[2].step_y, line[1].step_y);
  const __m256d one = _mm256_set1_pd(1.0), four = _mm256_set1_pd(4.0), row = _mm256_set1_pd(row_floats);
  // 2^52: an integer n < 2^52 added to it is exact, and the double's low 32 bits are then n.
  const __m256d integer_bias = _mm256_set1_pd(4503599627370496.0);
  alignas(32) std::int64_t offset[4];
  for (int x = first; x < last; ++x) {
    const __m256d f = _mm256_broadcast_sd(fraction + x);
    const __m256d at_x = _mm256_fmadd_pd(f, step_x, edge_x), at_y = _mm256_fmadd_pd(f, step_y, edge_y);
    const __m256d cell_x = _mm256_floor_pd(at_x), cell_y = _mm256_floor_pd(at_y);
    const __m256d fx = _mm256_sub_pd(at_x, cell_x), fy = _mm256_sub_pd(at_y, cell_y);
    // Each lane's corner offset in floats, cell_y row + 4 cell_x: exact in double (below 2^31).
    _mm256_store_pd(reinterpret_cast<double*>(offset), _mm256_fmadd_pd(cell_y, row, _mm256_fmadd_pd(cell_x, four, integer_bias)));
    // The weights' factors, each rounded once to float from its double (1 - f in double first, so
    // each keeps float's relative precision): (1 - fx, fx) side by side, 1 - fy and fy in both halves.
    const __m256 wx = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm256_cvtpd_ps(_mm256_sub_pd(one, fx))), _mm256_cvtpd_ps(fx), 1);
    const __m128 gy4 = _mm256_cvtpd_ps(_mm256_sub_pd(one, fy)), fy4 = _mm256_cvtpd_ps(fy);
    const __m256 wy_top = _mm256_insertf128_ps(_mm256_castps128_ps256(gy4), gy4, 1);
    const __m256 wy_bottom = _mm256_insertf128_ps(_mm256_castps128_ps256(fy4), fy4, 1);
    // Each lane's corner values from its channel's position (R, G, B from the red, green and blue
    // cells, alpha from the green), a corner row's two pixels in one load: lane k then weighs its
    // own channel's values by its own weights, with no weight moved between lanes.
    const float* red = scene + static_cast<std::uint32_t>(offset[0]);
    const float* green = scene + static_cast<std::uint32_t>(offset[1]);
    const float* blue = scene + static_cast<std::uint32_t>(offset[2]);
    const __m256 top =
        _mm256_blend_ps(_mm256_blend_ps(_mm256_loadu_ps(green), _mm256_loadu_ps(red), 0x11), _mm256_loadu_ps(blue), 0x44);
    const __m256 bottom = _mm256_blend_ps(
        _mm256_blend_ps(_mm256_loadu_ps(green + row_floats), _mm256_loadu_ps(red + row_floats), 0x11),
        _mm256_loadu_ps(blue + row_floats), 0x44);
    const __m256 sum = _mm256_mul_ps(wx, _mm256_fmadd_ps(bottom, wy_bottom, _mm256_mul_ps(top, wy_top)));
    _mm_storeu_ps(out_row + 4 * static_cast<std::ptrdiff_t>(x),
                  _mm_add_ps(_mm256_castps256_ps128(sum), _mm256_extractf128_ps(sum, 1)));
  }
}
#endif

}  // namespace

void warp_clear_span(const float* scene, int width_px, int height_px, const WarpCellLine line[3], const double* fraction,
                     int first, int last, float* out_row, VectorIsa isa) {
  const std::ptrdiff_t row_floats = 4 * static_cast<std::ptrdiff_t>(width_px);
#if defined(__x86_64__) && defined(__GNUC__)
  if (isa == VectorIsa::avx2_fma && row_floats * height_px < (std::int64_t{1} << 31)) {
    warp_clear_span_avx2(scene, static_cast<int>(row_floats), line, fraction, first, last, out_row);
    return;
  }
#else
  (void)isa;
  (void)height_px;
#endif
  warp_clear_span_sse2(scene, row_floats, line, fraction, first, last, out_row);
}

}  // namespace glarelab

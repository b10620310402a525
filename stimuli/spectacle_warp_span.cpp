#include "stimuli/spectacle_warp_span.h"

#include <array>
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
inline void warp_clear_span_sse2(const float* scene, std::ptrdiff_t row_floats, const WarpCellLine line[3], const double* fraction,
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
// The scene rows two and three below a corner's, which the next output rows read: asked for into
// the second-level cache a row ahead, so those rows' first reads find them there (the rows of
// one output row are not a stream the hardware's prefetcher follows across the frame's curve).
// Near the scene's last rows those addresses lie past its end: a prefetch never faults, and the
// address is formed as an integer, so no pointer past the array is ever made.
inline void prefetch_rows_below(const float* corner, int row_floats) {
  const std::uintptr_t at = reinterpret_cast<std::uintptr_t>(corner);
  const std::uintptr_t row_bytes = sizeof(float) * static_cast<std::uintptr_t>(row_floats);
  _mm_prefetch(reinterpret_cast<const char*>(at + 2 * row_bytes), _MM_HINT_T1);
  _mm_prefetch(reinterpret_cast<const char*>(at + 3 * row_bytes), _MM_HINT_T1);
}

// One channel-lane set of a row cell (lanes R, G, B, G: the fourth repeats green, whose position
// alpha takes too) and what a pixel's sample needs from its positions.
struct CellLanes {
  __m256d edge_x, edge_y, step_x, step_y;
};
struct PixelTaps {
  const float* red;  // the first float of each channel's cell's top-left corner
  const float* green;
  const float* blue;
  __m256 wx;         // (1 - fx, fx), four lanes each
  __m256 wy_top;     // 1 - fy in both halves
  __m256 wy_bottom;  // fy in both halves
};

// The cells and weights of the pixel at column fraction f: each lane's cell by a floor in double,
// its corner's offset in floats (cell_y row + 4 cell_x) as an integer-valued double whose low 32
// bits are the integer (2^52 added, exact below 2^31), and the weights' factors each rounded once
// to float from its double (1 - f in double first, so each keeps float's relative precision).
__attribute__((target("avx2,fma"))) inline PixelTaps pixel_taps(const float* scene, const CellLanes& cell, __m256d row, double f_value) {
  const __m256d one = _mm256_set1_pd(1.0), four = _mm256_set1_pd(4.0), integer_bias = _mm256_set1_pd(4503599627370496.0);
  const __m256d f = _mm256_set1_pd(f_value);
  const __m256d at_x = _mm256_fmadd_pd(f, cell.step_x, cell.edge_x), at_y = _mm256_fmadd_pd(f, cell.step_y, cell.edge_y);
  const __m256d cell_x = _mm256_floor_pd(at_x), cell_y = _mm256_floor_pd(at_y);
  const __m256d fx = _mm256_sub_pd(at_x, cell_x), fy = _mm256_sub_pd(at_y, cell_y);
  const __m256i offset = _mm256_castpd_si256(_mm256_fmadd_pd(cell_y, row, _mm256_fmadd_pd(cell_x, four, integer_bias)));
  const __m128i low = _mm256_castsi256_si128(offset);
  PixelTaps taps;
  taps.red = scene + static_cast<std::uint32_t>(_mm_cvtsi128_si32(low));
  taps.green = scene + static_cast<std::uint32_t>(_mm_extract_epi32(low, 2));
  taps.blue = scene + static_cast<std::uint32_t>(_mm_cvtsi128_si32(_mm256_extracti128_si256(offset, 1)));
  taps.wx = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm256_cvtpd_ps(_mm256_sub_pd(one, fx))), _mm256_cvtpd_ps(fx), 1);
  const __m128 gy4 = _mm256_cvtpd_ps(_mm256_sub_pd(one, fy)), fy4 = _mm256_cvtpd_ps(fy);
  taps.wy_top = _mm256_insertf128_ps(_mm256_castps128_ps256(gy4), gy4, 1);
  taps.wy_bottom = _mm256_insertf128_ps(_mm256_castps128_ps256(fy4), fy4, 1);
  return taps;
}

// Each lane's corner values from its channel's position (R, G, B from the red, green and blue
// cells, alpha from the green), a corner row's two pixels in one load: lane k then weighs its own
// channel's values by its own weights, with no weight moved between lanes.
struct Corners {
  __m256 top, bottom;  // (top-left, top-right), (bottom-left, bottom-right)
};
__attribute__((target("avx2,fma"))) inline Corners load_corners(const PixelTaps& taps, int row_floats) {
  const float* const below[3] = {taps.red + row_floats, taps.green + row_floats, taps.blue + row_floats};
  return {_mm256_blend_ps(_mm256_blend_ps(_mm256_loadu_ps(taps.green), _mm256_loadu_ps(taps.red), 0x11), _mm256_loadu_ps(taps.blue), 0x44),
          _mm256_blend_ps(_mm256_blend_ps(_mm256_loadu_ps(below[1]), _mm256_loadu_ps(below[0]), 0x11), _mm256_loadu_ps(below[2]), 0x44)};
}

__attribute__((target("avx2,fma"))) inline void warp_clear_span_avx2(const float* scene, int row_floats, const WarpCellLine line[3],
                                                                      const double* fraction, int first, int last, float* out_row) {
  if (first >= last) return;
  const CellLanes cell{_mm256_setr_pd(line[0].edge_x, line[1].edge_x, line[2].edge_x, line[1].edge_x),
                       _mm256_setr_pd(line[0].edge_y, line[1].edge_y, line[2].edge_y, line[1].edge_y),
                       _mm256_setr_pd(line[0].step_x, line[1].step_x, line[2].step_x, line[1].step_x),
                       _mm256_setr_pd(line[0].step_y, line[1].step_y, line[2].step_y, line[1].step_y)};
  const __m256d row = _mm256_set1_pd(row_floats);
  // Each pixel's cells and weights found one pixel ahead: its loads then wait on no arithmetic of
  // their own iteration, and the next pixel's position arithmetic runs beside them.
  PixelTaps taps = pixel_taps(scene, cell, row, fraction[first]);
  for (int x = first; x < last; ++x) {
    prefetch_rows_below(taps.green, row_floats);
    const Corners corners = load_corners(taps, row_floats);
    const PixelTaps next = pixel_taps(scene, cell, row, fraction[x + 1 < last ? x + 1 : x]);
    const __m256 sum =
        _mm256_mul_ps(taps.wx, _mm256_fmadd_ps(corners.bottom, taps.wy_bottom, _mm256_mul_ps(corners.top, taps.wy_top)));
    _mm_storeu_ps(out_row + 4 * static_cast<std::ptrdiff_t>(x), _mm_add_ps(_mm256_castps256_ps128(sum), _mm256_extractf128_ps(sum, 1)));
    taps = next;
  }
}

// GCC 12's AVX-512 intrinsics pass an undefined vector as the source of lanes no mask selects,
// which -Wmaybe-uninitialized reports at every use.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

// Two pixels at a time: eight double lanes, pixel x's R, G, B, G then pixel x + 1's.
struct CellLanes8 {
  __m512d edge_x, edge_y, step_x, step_y;
};
struct PairTaps {
  const float* red[2];  // pixel k's channels' cells, as PixelTaps
  const float* green[2];
  const float* blue[2];
  __m512 weight[2];  // pixel k's corner weights (top-left, top-right, bottom-left, bottom-right), four lanes each
};

// The cells and weights of pixels x and x + 1 (fractions f_pair[0], [1]): the cells and offsets as
// pixel_taps finds them, the four corner weights as products in double each rounded once to float.
__attribute__((target("avx512f,avx512vl,avx512dq,avx2,fma"))) inline PairTaps pair_taps(const float* scene, const CellLanes8& cell,
                                                                                       __m512d row, const double* f_pair) {
  const __m512d one = _mm512_set1_pd(1.0), four = _mm512_set1_pd(4.0), integer_bias = _mm512_set1_pd(4503599627370496.0);
  const __m512d f = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_set1_pd(f_pair[0])), _mm256_set1_pd(f_pair[1]), 1);
  const __m512d at_x = _mm512_fmadd_pd(f, cell.step_x, cell.edge_x), at_y = _mm512_fmadd_pd(f, cell.step_y, cell.edge_y);
  const __m512d cell_x = _mm512_roundscale_pd(at_x, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
  const __m512d cell_y = _mm512_roundscale_pd(at_y, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
  const __m512d fx = _mm512_sub_pd(at_x, cell_x), fy = _mm512_sub_pd(at_y, cell_y);
  const __m512i offset = _mm512_castpd_si512(_mm512_fmadd_pd(cell_y, row, _mm512_fmadd_pd(cell_x, four, integer_bias)));
  const __m256i first_pixel = _mm512_castsi512_si256(offset), second_pixel = _mm512_extracti64x4_epi64(offset, 1);
  const __m128i red_green0 = _mm256_castsi256_si128(first_pixel), blue0 = _mm256_extracti128_si256(first_pixel, 1);
  const __m128i red_green1 = _mm256_castsi256_si128(second_pixel), blue1 = _mm256_extracti128_si256(second_pixel, 1);
  PairTaps taps;
  taps.red[0] = scene + static_cast<std::uint32_t>(_mm_cvtsi128_si32(red_green0));
  taps.green[0] = scene + static_cast<std::uint32_t>(_mm_extract_epi32(red_green0, 2));
  taps.blue[0] = scene + static_cast<std::uint32_t>(_mm_cvtsi128_si32(blue0));
  taps.red[1] = scene + static_cast<std::uint32_t>(_mm_cvtsi128_si32(red_green1));
  taps.green[1] = scene + static_cast<std::uint32_t>(_mm_extract_epi32(red_green1, 2));
  taps.blue[1] = scene + static_cast<std::uint32_t>(_mm_cvtsi128_si32(blue1));
  const __m512d gx = _mm512_sub_pd(one, fx), gy = _mm512_sub_pd(one, fy);
  const __m256 w_tl = _mm512_cvtpd_ps(_mm512_mul_pd(gy, gx)), w_tr = _mm512_cvtpd_ps(_mm512_mul_pd(gy, fx));
  const __m256 w_bl = _mm512_cvtpd_ps(_mm512_mul_pd(fy, gx)), w_br = _mm512_cvtpd_ps(_mm512_mul_pd(fy, fx));
  const __m512 w_top = _mm512_insertf32x8(_mm512_castps256_ps512(w_tl), w_tr, 1);
  const __m512 w_bottom = _mm512_insertf32x8(_mm512_castps256_ps512(w_bl), w_br, 1);
  taps.weight[0] = _mm512_shuffle_f32x4(w_top, w_bottom, 0x88);  // quarters 0, 2 of each: pixel x's
  taps.weight[1] = _mm512_shuffle_f32x4(w_top, w_bottom, 0xdd);  // quarters 1, 3: pixel x + 1's
  return taps;
}

// Pixel k's four corners (top-left, top-right, bottom-left, bottom-right), as load_corners finds them.
__attribute__((target("avx512f,avx512vl,avx512dq,avx2,fma"))) inline __m512 pair_corners(const PairTaps& taps, int k, int row_floats) {
  const float* const below[3] = {taps.red[k] + row_floats, taps.green[k] + row_floats, taps.blue[k] + row_floats};
  const Corners corners{
      _mm256_blend_ps(_mm256_blend_ps(_mm256_loadu_ps(taps.green[k]), _mm256_loadu_ps(taps.red[k]), 0x11), _mm256_loadu_ps(taps.blue[k]), 0x44),
      _mm256_blend_ps(_mm256_blend_ps(_mm256_loadu_ps(below[1]), _mm256_loadu_ps(below[0]), 0x11), _mm256_loadu_ps(below[2]), 0x44)};
  return _mm512_insertf32x8(_mm512_castps256_ps512(corners.top), corners.bottom, 1);
}

__attribute__((target("avx512f,avx512vl,avx512dq,avx2,fma"))) void warp_clear_span_avx512(const float* scene, int row_floats,
                                                                                         const WarpCellLine line[3], const double* fraction,
                                                                                         int first, int last, float* out_row) {
  if (last - first < 4) {
    warp_clear_span_avx2(scene, row_floats, line, fraction, first, last, out_row);
    return;
  }
  const auto lanes = [](double r, double g, double b) { return std::array<double, 8>{r, g, b, g, r, g, b, g}; };
  const std::array<double, 8> edge_x = lanes(line[0].edge_x, line[1].edge_x, line[2].edge_x);
  const std::array<double, 8> edge_y = lanes(line[0].edge_y, line[1].edge_y, line[2].edge_y);
  const std::array<double, 8> step_x = lanes(line[0].step_x, line[1].step_x, line[2].step_x);
  const std::array<double, 8> step_y = lanes(line[0].step_y, line[1].step_y, line[2].step_y);
  const CellLanes8 cell{_mm512_loadu_pd(edge_x.data()), _mm512_loadu_pd(edge_y.data()), _mm512_loadu_pd(step_x.data()),
                        _mm512_loadu_pd(step_y.data())};
  const __m512d row = _mm512_set1_pd(row_floats);
  // As the AVX2 form, each pair's cells and weights found one pair ahead.
  const int pairs_last = first + ((last - first) & ~1);
  PairTaps taps = pair_taps(scene, cell, row, fraction + first);
  for (int x = first; x < pairs_last; x += 2) {
    prefetch_rows_below(taps.green[0], row_floats);
    const __m512 product0 = _mm512_mul_ps(pair_corners(taps, 0, row_floats), taps.weight[0]);
    const __m512 product1 = _mm512_mul_ps(pair_corners(taps, 1, row_floats), taps.weight[1]);
    if (x + 2 < pairs_last) taps = pair_taps(scene, cell, row, fraction + x + 2);
    // Each pixel's four quarters summed: (TL + BL, TR + BR) of both pixels, then the pairs.
    const __m512 columns = _mm512_add_ps(_mm512_shuffle_f32x4(product0, product1, 0x44), _mm512_shuffle_f32x4(product0, product1, 0xee));
    const __m512 sums = _mm512_add_ps(_mm512_shuffle_f32x4(columns, columns, 0x08), _mm512_shuffle_f32x4(columns, columns, 0x0d));
    _mm256_storeu_ps(out_row + 4 * static_cast<std::ptrdiff_t>(x), _mm512_castps512_ps256(sums));
  }
  // An odd cell's last pixel by the AVX2 form.
  if (pairs_last < last) warp_clear_span_avx2(scene, row_floats, line, fraction, pairs_last, last, out_row);
}

// A row's cells in one call, so each cell costs its lines' set-up and no call of its own.
__attribute__((target("avx2,fma"))) void warp_clear_cells_avx2(const float* scene, int row_floats, const WarpCellLine* lines,
                                                                const int* cell_first, int first_cell, int last_cell,
                                                                const double* fraction, float* out_row) {
  for (int i = first_cell; i < last_cell; ++i)
    warp_clear_span_avx2(scene, row_floats, lines + 3 * static_cast<std::ptrdiff_t>(i), fraction, cell_first[i], cell_first[i + 1], out_row);
}
__attribute__((target("avx512f,avx512vl,avx512dq,avx2,fma"))) void warp_clear_cells_avx512(
    const float* scene, int row_floats, const WarpCellLine* lines, const int* cell_first, int first_cell, int last_cell,
    const double* fraction, float* out_row) {
  for (int i = first_cell; i < last_cell; ++i)
    warp_clear_span_avx512(scene, row_floats, lines + 3 * static_cast<std::ptrdiff_t>(i), fraction, cell_first[i], cell_first[i + 1], out_row);
}

#pragma GCC diagnostic pop

// The AVX2 and AVX-512 forms address the scene with 32-bit offsets.
bool wide_form_fits(VectorIsa isa, std::ptrdiff_t row_floats, int height_px) {
  return isa != VectorIsa::sse2 && row_floats * height_px < (std::int64_t{1} << 31);
}
#endif

}  // namespace

void warp_clear_span(const float* scene, int width_px, int height_px, const WarpCellLine line[3], const double* fraction,
                     int first, int last, float* out_row, VectorIsa isa) {
  const std::ptrdiff_t row_floats = 4 * static_cast<std::ptrdiff_t>(width_px);
#if defined(__x86_64__) && defined(__GNUC__)
  if (wide_form_fits(isa, row_floats, height_px)) {
    if (isa == VectorIsa::avx512)
      warp_clear_span_avx512(scene, static_cast<int>(row_floats), line, fraction, first, last, out_row);
    else
      warp_clear_span_avx2(scene, static_cast<int>(row_floats), line, fraction, first, last, out_row);
    return;
  }
#else
  (void)isa;
  (void)height_px;
#endif
  warp_clear_span_sse2(scene, row_floats, line, fraction, first, last, out_row);
}

void warp_clear_cells(const float* scene, int width_px, int height_px, const WarpCellLine* lines, const int* cell_first,
                      int first_cell, int last_cell, const double* fraction, float* out_row, VectorIsa isa) {
  const std::ptrdiff_t row_floats = 4 * static_cast<std::ptrdiff_t>(width_px);
#if defined(__x86_64__) && defined(__GNUC__)
  if (wide_form_fits(isa, row_floats, height_px)) {
    if (isa == VectorIsa::avx512)
      warp_clear_cells_avx512(scene, static_cast<int>(row_floats), lines, cell_first, first_cell, last_cell, fraction, out_row);
    else
      warp_clear_cells_avx2(scene, static_cast<int>(row_floats), lines, cell_first, first_cell, last_cell, fraction, out_row);
    return;
  }
#else
  (void)isa;
  (void)height_px;
#endif
  for (int i = first_cell; i < last_cell; ++i)
    warp_clear_span_sse2(scene, row_floats, lines + 3 * static_cast<std::ptrdiff_t>(i), fraction, cell_first[i], cell_first[i + 1], out_row);
}

}  // namespace glarelab

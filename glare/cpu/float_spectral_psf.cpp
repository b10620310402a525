#include "glare/cpu/float_spectral_psf.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "core/parallel_for.h"
#include "glare/wave/cie_cmf.h"
#include "glare/wave/psf_scale.h"

namespace glarelab {

namespace {

// rows x [c0, c1) of `source` (rows `source_stride` apart) written transposed: value (r, k) to
// target[k * target_stride + r]. In 4 x 4 blocks of SSE registers where the compiler has them (x86-64
// always does): the compiler made the element-by-element copy one scalar load and store per value,
// 14 % of the spectral stage's time. A copy: the values are the same bits either way.
void transpose_tile(const float* source, int source_stride, int rows, int c0, int c1, float* target, int target_stride) {
  const auto at = [](int index, int stride) { return static_cast<std::size_t>(index) * static_cast<std::size_t>(stride); };
  int k = c0;
#if defined(__SSE__)
  for (; k + 4 <= c1; k += 4) {
    int r = 0;
    for (; r + 4 <= rows; r += 4) {
      __m128 row0 = _mm_loadu_ps(source + at(r, source_stride) + k);
      __m128 row1 = _mm_loadu_ps(source + at(r + 1, source_stride) + k);
      __m128 row2 = _mm_loadu_ps(source + at(r + 2, source_stride) + k);
      __m128 row3 = _mm_loadu_ps(source + at(r + 3, source_stride) + k);
      _MM_TRANSPOSE4_PS(row0, row1, row2, row3);
      _mm_storeu_ps(target + at(k, target_stride) + r, row0);
      _mm_storeu_ps(target + at(k + 1, target_stride) + r, row1);
      _mm_storeu_ps(target + at(k + 2, target_stride) + r, row2);
      _mm_storeu_ps(target + at(k + 3, target_stride) + r, row3);
    }
    for (; r < rows; ++r)
      for (int j = 0; j < 4; ++j) target[at(k + j, target_stride) + r] = source[at(r, source_stride) + k + j];
  }
#endif
  for (; k < c1; ++k)
    for (int r = 0; r < rows; ++r) target[at(k, target_stride) + r] = source[at(r, source_stride) + k];
}

// The D values (float) of `count` wavelengths for a tile of display rows [m0, m0 + rows) summed into
// R, G, B and their magnitudes (six double planes, `plane` apart, transposed: index m' M + m), each
// sum in the wavelengths' order from 0. tile_d holds wavelength s's D(m0 + r, m') at
// (s M + m') 8 + r, just written by reduce_tile and still in cache; weights[p count + s] is sum p's
// weight of wavelength s (p: R, |R|, G, |G|, B, |B|). Four rows a step in vectors of four doubles
// (as scalars, the six sums did not fit the registers); each product rounded, then added, in every
// clone: the same bits.
using Double4 = double __attribute__((vector_size(32)));
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__SANITIZE_ADDRESS__)
__attribute__((target_clones("avx2", "default")))
#endif
void add_wavelengths(const float* __restrict tile_d, int count, int columns, int m0, int rows, std::size_t plane,
                     const double* weights, double* __restrict rgb_t) {
  using Float4 = float __attribute__((vector_size(16)));
  const std::size_t wavelength_stride = static_cast<std::size_t>(columns) * 8;
  const auto weight = [&](int p, int s) { return weights[static_cast<std::size_t>(p * count + s)]; };
  // Planes in the order of the weights: R, |R|, G, |G|, B, |B| (rgb_t holds R, G, B, |R|, |G|, |B|).
  constexpr std::size_t kPlane[6] = {0, 3, 1, 4, 2, 5};
  for (int column = 0; column < columns; ++column) {
    const std::size_t first = static_cast<std::size_t>(column) * static_cast<std::size_t>(columns) + static_cast<std::size_t>(m0);
    const float* d_column = tile_d + static_cast<std::size_t>(column) * 8;
    int row = 0;
    for (; row + 4 <= rows; row += 4) {
      Double4 sums[6] = {};
      for (int s = 0; s < count; ++s) {
        Float4 value;
        std::memcpy(&value, d_column + static_cast<std::size_t>(s) * wavelength_stride + row, sizeof value);
        const Double4 d = __builtin_convertvector(value, Double4);
        for (int p = 0; p < 6; ++p) sums[p] += weight(p, s) * d;
      }
      for (int p = 0; p < 6; ++p) std::memcpy(rgb_t + kPlane[p] * plane + first + row, &sums[p], sizeof(Double4));
    }
    for (; row < rows; ++row) {
      double sums[6] = {};
      for (int s = 0; s < count; ++s) {
        const double d = d_column[static_cast<std::size_t>(s) * wavelength_stride + row];
        for (int p = 0; p < 6; ++p) sums[p] += weight(p, s) * d;
      }
      for (int p = 0; p < 6; ++p) rgb_t[kPlane[p] * plane + first + row] = sums[p];
    }
  }
}

// out[0, length) = sum over j < count of weights[j] times row j of `sources` (rows `stride` apart),
// added in j's order from 0, as the element-by-element loops did. Cloned for AVX2 where the compiler
// can (the ifunc picks the clone at load time): 8 floats a step instead of SSE's 4 in the spectral
// stage's pass along the reference rows. AVX2 without FMA: each product is rounded, then added, as
// on SSE, so both clones give the same bits. (Keeping 32 outputs in registers while the rows are
// added, so that each is written once, was slower here: 2.0 against 1.6 ms for the row pass's loops.)
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__SANITIZE_ADDRESS__)
__attribute__((target_clones("avx2", "default")))
#endif
void weighted_row_sum(float* __restrict out, int length, const float* weights, int count,
                      const float* __restrict sources, std::size_t stride) {
  // The first row's products start the sums (0 + p = p: the weights and the power are >= 0, so no
  // product is -0), in place of a pass that clears `out`.
  if (count <= 0) {
    std::fill(out, out + length, 0.0f);
    return;
  }
  for (int k = 0; k < length; ++k) out[k] = weights[0] * sources[k];
  for (int j = 1; j < count; ++j) {
    const float weight = weights[j];
    const float* source = sources + static_cast<std::size_t>(j) * stride;
    for (int k = 0; k < length; ++k) out[k] += weight * source[k];
  }
}

// The pass along the reference columns for a tile of display rows m0 + r, r < rows <= 8:
// out[m' 8 + r] = sum over k < count of W(m', first + k) (W F)(m0 + r, first + k) for every
// display column m' (its band: first, count, weights from offset), read from
// tile_t[x * 8 + r] = (W F)(m0 + r, x). Eight rows in one vector a step, each sum added in k's order
// from 0, each product rounded and then added in every clone: the same bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__SANITIZE_ADDRESS__)
__attribute__((target_clones("avx2", "default")))
#endif
void reduce_tile(const float* __restrict tile_t, const CpuFloatSpectralPsf::Band* bands, const float* weights,
                 int columns, int rows, float* __restrict out) {
  using Lane = float __attribute__((vector_size(32)));
  // sum += w (W F)(rows, first + k), and the sum's rows stored, without functions that take or
  // return a vector (their ABI would differ between the clones).
  const auto add = [&](Lane& sum, const CpuFloatSpectralPsf::Band& band, int k) {
    Lane value;
    std::memcpy(&value, tile_t + (static_cast<std::size_t>(band.first) + static_cast<std::size_t>(k)) * 8, sizeof value);
    sum += weights[band.offset + k] * value;
  };
  // A whole vector where the tile has 8 rows: a copy of a fixed size is a store, one of `rows`
  // floats a call to memcpy per display column.
  const auto store = [&](int column, const Lane& sum) {
    float* target = out + static_cast<std::size_t>(column) * 8;
    if (rows == 8)
      std::memcpy(target, &sum, sizeof sum);
    else
      std::memcpy(target, &sum, static_cast<std::size_t>(rows) * sizeof(float));
  };
  // Four display columns at a time: four independent sums, where one sum's chain of additions kept
  // the loop waiting on each addition's latency.
  constexpr int kColumns = 4;
  int column = 0;
  for (; column + kColumns <= columns; column += kColumns) {
    const CpuFloatSpectralPsf::Band* band = bands + column;
    Lane sum[kColumns] = {};
    int shared = band[0].count;
    for (int c = 1; c < kColumns; ++c) shared = std::min(shared, band[c].count);
    for (int k = 0; k < shared; ++k)
      for (int c = 0; c < kColumns; ++c) add(sum[c], band[c], k);
    for (int c = 0; c < kColumns; ++c) {
      for (int k = shared; k < band[c].count; ++k) add(sum[c], band[c], k);
      store(column + c, sum[c]);
    }
  }
  for (; column < columns; ++column) {
    const CpuFloatSpectralPsf::Band& band = bands[column];
    Lane sum = {};
    for (int k = 0; k < band.count; ++k) add(sum, band, k);
    store(column, sum);
  }
}

// The refinement's loops (spectral_block). Along x: h[i] = weight0[i] source[index0[i]] +
// weight1[i] source[index1[i]] for consecutive PSF columns, where the indices never fall and eight
// consecutive outputs read at most 16 consecutive source values (checked per wavelength: `compact`).
// The compiler made the two reads of every output scalar loads (two thirds of the refinement's
// time); with AVX2, eight outputs take two loads of eight source values and a permutation of each
// (vpermps) in their place. The products and the sum are rounded as the scalar loop rounds them
// (no fused multiply-add), so both give the same bits.
void interpolate_along_row_scalar(const float* __restrict source, const int* index0, const int* index1,
                                  const float* weight0, const float* weight1, std::size_t begin, std::size_t end,
                                  float* __restrict h) {
  for (std::size_t i = begin; i < end; ++i) h[i] = weight0[i] * source[index0[i]] + weight1[i] * source[index1[i]];
}

#if defined(__x86_64__) && defined(__GNUC__)
// source[base + at[k]] for at[k] in [0, 16): `low` holds source[base, base + 8), `high` the next 8.
__attribute__((target("avx2"))) inline __m256 permuted_read(__m256 low, __m256 high, __m256i at) {
  const __m256 from_low = _mm256_permutevar8x32_ps(low, at), from_high = _mm256_permutevar8x32_ps(high, at);
  return _mm256_blendv_ps(from_low, from_high, _mm256_castsi256_ps(_mm256_cmpgt_epi32(at, _mm256_set1_epi32(7))));
}

__attribute__((target("avx2"))) void interpolate_along_row_avx2(const float* __restrict source, int length,
                                                                  const int* index0, const int* index1,
                                                                  const float* weight0, const float* weight1,
                                                                  std::size_t width, float* __restrict h) {
  std::size_t i = 0;
  for (; i + 8 <= width; i += 8) {
    const int base = index0[i];
    if (base + 16 > length) break;  // the loads would pass the row's end: the rest one by one
    const __m256 low = _mm256_loadu_ps(source + base), high = _mm256_loadu_ps(source + base + 8);
    const __m256i offset = _mm256_set1_epi32(base);
    const __m256i at0 = _mm256_sub_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(index0 + i)), offset);
    const __m256i at1 = _mm256_sub_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(index1 + i)), offset);
    const __m256 product0 = _mm256_mul_ps(_mm256_loadu_ps(weight0 + i), permuted_read(low, high, at0));
    const __m256 product1 = _mm256_mul_ps(_mm256_loadu_ps(weight1 + i), permuted_read(low, high, at1));
    _mm256_storeu_ps(h + i, _mm256_add_ps(product0, product1));
  }
  interpolate_along_row_scalar(source, index0, index1, weight0, weight1, i, width, h);
}
#endif

void interpolate_along_row(const float* __restrict source, int length, const int* index0, const int* index1,
                           const float* weight0, const float* weight1, std::size_t width, bool compact,
                           float* __restrict h) {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (compact && avx2) {
    interpolate_along_row_avx2(source, length, index0, index1, weight0, weight1, width, h);
    return;
  }
#else
  (void)length;
  (void)compact;
#endif
  interpolate_along_row_scalar(source, index0, index1, weight0, weight1, 0, width, h);
}

// Along y, then into R, G, B (float): v = wy0 h0[i] + wy1 h1[i], each channel += its weight times v.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__SANITIZE_ADDRESS__)
__attribute__((target_clones("avx2", "default")))
#endif
void add_interpolated_column(const float* __restrict h0, const float* __restrict h1, float wy0, float wy1,
                             const float* rgb_weight, std::size_t width, float* __restrict red,
                             float* __restrict green, float* __restrict blue) {
  const float r = rgb_weight[0], g = rgb_weight[1], b = rgb_weight[2];
  for (std::size_t i = 0; i < width; ++i) {
    const float v = wy0 * h0[i] + wy1 * h1[i];
    red[i] += r * v;
    green[i] += g * v;
    blue[i] += b * v;
  }
}

}  // namespace

void CpuFloatSpectralPsf::spectral_block(const float* power, const std::vector<BlockSegment>& segments, int width_px,
                                         const std::vector<PsfOverlap>& ys, std::vector<float>& rgb) const {
  const int n = settings_.grid_px;
  const std::size_t width = static_cast<std::size_t>(width_px), height = ys.size();
  rgb.assign(3 * width * height, 0.0f);
  // Bilinear per wavelength as glare/wave/spectral_psf.cpp, separably: each reference row the block reads is
  // interpolated along x once (consecutive PSF rows share their neighbour rows), then along y.
  thread_local std::vector<float> scratch;
  scratch.resize(2 * width);
  float *h0 = scratch.data(), *h1 = h0 + width;
  for (const Wavelength& wavelength : wavelengths_) {
    const auto interpolate_row = [&](int row, float* h) {
      const float* source = power + static_cast<std::size_t>(row) * n;
      for (const BlockSegment& segment : segments) {
        const auto column = static_cast<std::size_t>(segment.first_column);
        interpolate_along_row(source, n, &wavelength.index0[column], &wavelength.index1[column],
                              &wavelength.weight0[column], &wavelength.weight1[column],
                              static_cast<std::size_t>(segment.columns), wavelength.compact, h + segment.offset);
      }
    };
    int row0 = -1, row1 = -1;  // the reference rows h0 and h1 hold
    for (std::size_t j = 0; j < height; ++j) {
      const auto y = static_cast<std::size_t>(ys[j].input);
      const int next0 = wavelength.index0[y], next1 = wavelength.index1[y];
      if (next0 == row1 && next0 != row0) {  // moved down one row: the lower neighbour becomes the upper
        std::swap(h0, h1);
        std::swap(row0, row1);
      }
      if (next0 != row0) {
        interpolate_row(next0, h0);
        row0 = next0;
      }
      if (next1 != row1) {
        interpolate_row(next1, h1);
        row1 = next1;
      }
      const float wy0 = wavelength.weight0[y], wy1 = wavelength.weight1[y];
      // data(): an empty block (width 0) has no element 0 to take the address of.
      float* red = rgb.data() + j * width;
      float* green = red + height * width;
      float* blue = green + height * width;
      add_interpolated_column(h0, h1, wy0, wy1, wavelength.rgb_weight_float, width, red, green, blue);
    }
  }
}

// The tiles' pass into totals_ (compute()).
void CpuFloatSpectralPsf::add_spectral_tiles(const float* power) {
  const int n = settings_.grid_px, m_px = display_px_;
  const std::size_t plane = static_cast<std::size_t>(m_px) * m_px;
  // kTile display rows at a time, the tiles shared among the threads; per tile and wavelength,
  // (W F)(m, :) = sum_j W(m, first + j) F(first + j, :) (along the reference rows), transposed into
  // tile_t, then D(m, m') = sum_k W(m', first + k) (W F)(m, first + k) for all m' (along the reference
  // columns), kTile rows m in one vector, into tile_d; then the tile's D of all the wavelengths added
  // to R, G, B and their magnitudes in one pass, each sum in the wavelengths' order (so the result
  // does not depend on the thread count). The D values are read while in cache and the six double
  // planes are written once.
  static_assert(kTile == 8, "reduce_tile and add_wavelengths take 8 rows a step");
  const int tile_count = (m_px + kTile - 1) / kTile;
  const int active_count = static_cast<int>(active_.size());
  std::vector<double>& total = totals_;
  parallel_indexed_chunks(tile_count, settings_.threads, [&](int chunk, int first_tile, int last_tile) {
    TileScratch& scratch = scratch_[static_cast<std::size_t>(chunk)];
    for (int tile = first_tile; tile < last_tile; ++tile) {
      const int m0 = tile * kTile, tile_rows = std::min(kTile, m_px - m0);
      for (int s = 0; s < active_count; ++s) {
        const Wavelength& wavelength = wavelengths_[static_cast<std::size_t>(active_[static_cast<std::size_t>(s)])];
        const int c0 = wavelength.first_column, c1 = wavelength.last_column + 1;
        for (int r = 0; r < tile_rows; ++r) {
          const Band& band = wavelength.bands[static_cast<std::size_t>(m0 + r)];
          float* row = scratch.row.data() + static_cast<std::size_t>(r) * n;
          weighted_row_sum(row + c0, c1 - c0, &weights_[static_cast<std::size_t>(band.offset)], band.count,
                           power + static_cast<std::size_t>(band.first) * n + c0, static_cast<std::size_t>(n));
        }
        transpose_tile(scratch.row.data(), n, tile_rows, c0, c1, scratch.tile_t.data(), kTile);
        reduce_tile(scratch.tile_t.data(), wavelength.bands.data(), weights_.data(), m_px, tile_rows,
                    &scratch.tile_d[static_cast<std::size_t>(s) * m_px * kTile]);
      }
      add_wavelengths(scratch.tile_d.data(), active_count, m_px, m0, tile_rows, plane, sum_weights_.data(), total.data());
    }
  });
}

// The screen: straddles_ set on the display pixels whose clamp is done on PSF pixels (compute()).
void CpuFloatSpectralPsf::screen_straddles(double pupil_diameter_mm) {
  const int m_px = display_px_;
  const std::size_t plane = static_cast<std::size_t>(m_px) * m_px;
  const std::vector<double>& total = totals_;
  // The clamp. glare/wave/spectral_psf.cpp clamps negative R, G, B on PSF pixels, before the box resampling;
  // clamping the box means instead differs wherever a display pixel's PSF pixels do not all have
  // the same sign (1e-5 of the frame on the eye model's PSFs). Where a channel's sign can change
  // inside a display pixel, the pixel is computed as the double path does, from the PSF pixels it
  // covers, clamped one by one: where its display value is a small part of the magnitude of its
  // wavelengths' contributions, |R| < kStraddle sum_i |w_i| F_i; where a neighbouring display pixel
  // has the other sign (the zero runs close by); and in the core (below). This is a screen, not a
  // bound: elsewhere the sign is taken to be the same all over the pixel and the box mean is
  // clamped; tests/glare_cpu_float_test.cpp and `glarelab bench` check the result against the
  // double path on the eye model's apertures.
  // Spectral PSF error against the float64 path with these (eye model at 1.2 s, 32 wavelengths):
  // 4e-8, 4e-7, 2e-7 at N = 256, 512, 1024, refining 29 %, 14 %, 10 % of the display pixels.
  // Without the neighbour test kStraddle = 0.5 was needed for 1e-7 (and refined twice as many);
  // without the core disk the error was 4e-5 (the red channel's ring at 9.5 PSF pixels).
  constexpr double kStraddle = 0.3, kCoreRings = 8.0;
  // Around the core the rings of each wavelength sit at radii proportional to it (1.22, 2.23, ...
  // lambda / D, Born and Wolf 8.5.2), so a channel changes sign from one PSF pixel to the next
  // there while the box mean stays large: the display pixels within kCoreRings lambda_max / D of the
  // centre are always refined.
  const double longest_nm = spectral_samples(settings_.wavelength_samples).back().wavelength_nm;
  const double core_radius_display_px = kCoreRings * (longest_nm / settings_.reference_wavelength_nm) *
                                        (settings_.aperture_width_mm / pupil_diameter_mm) *
                                        settings_.psf_degrees_per_pixel / settings_.display_degrees_per_pixel;
  // The screen, in passes that vectorise (the per-pixel loops with their early exits took a tenth
  // of the stage): negative_ holds a bit per channel, set where it is negative; its OR and AND over
  // each pixel's 3 x 3 neighbourhood (clipped at the edges) are taken first along y (along_y_any_,
  // along_y_all_: contiguous, the planes are transposed), then along x. A channel has a neighbour of the
  // other sign exactly where its OR is set and its AND is not (the pixel is in its own
  // neighbourhood). Each pass writes only its own display columns.
  const auto column = [&](int mx) { return static_cast<std::size_t>(mx) * static_cast<std::size_t>(m_px); };
  parallel_chunks(m_px, settings_.threads, [&](int first, int last) {
    for (std::size_t k = column(first); k < column(last); ++k)
      negative_[k] = static_cast<unsigned char>((total[k] < 0.0 ? 1 : 0) | (total[plane + k] < 0.0 ? 2 : 0) |
                                                (total[2 * plane + k] < 0.0 ? 4 : 0));
  });
  parallel_chunks(m_px, settings_.threads, [&](int first, int last) {
    for (int mx = first; mx < last; ++mx) {
      const unsigned char* in = &negative_[column(mx)];
      unsigned char* any = &along_y_any_[column(mx)];
      unsigned char* all = &along_y_all_[column(mx)];
      for (int my = 0; my < m_px; ++my) {
        const unsigned char here = in[my], before = my > 0 ? in[my - 1] : here, after = my + 1 < m_px ? in[my + 1] : here;
        any[my] = static_cast<unsigned char>(before | here | after);
        all[my] = static_cast<unsigned char>(before & here & after);
      }
    }
  });
  parallel_chunks(m_px, settings_.threads, [&](int first, int last) {
    for (int mx = first; mx < last; ++mx) {
      const int left = std::max(0, mx - 1), right = std::min(m_px - 1, mx + 1);
      const unsigned char *any0 = &along_y_any_[column(left)], *any1 = &along_y_any_[column(mx)], *any2 = &along_y_any_[column(right)];
      const unsigned char *all0 = &along_y_all_[column(left)], *all1 = &along_y_all_[column(mx)], *all2 = &along_y_all_[column(right)];
      const double* net[3] = {&total[column(mx)], &total[plane + column(mx)], &total[2 * plane + column(mx)]};
      const double* size[3] = {&total[3 * plane + column(mx)], &total[4 * plane + column(mx)], &total[5 * plane + column(mx)]};
      unsigned char* out = &straddles_[column(mx)];
      const double dx = static_cast<double>(mx) - m_px / 2;
      for (int my = 0; my < m_px; ++my) {
        const unsigned char any = static_cast<unsigned char>(any0[my] | any1[my] | any2[my]);
        const unsigned char all = static_cast<unsigned char>(all0[my] & all1[my] & all2[my]);
        bool straddles = (any & ~all) != 0;
        // A value that is a small part of its wavelengths' magnitudes.
        for (int c = 0; c < 3; ++c) straddles |= size[c][my] > 0.0 && std::abs(net[c][my]) < kStraddle * size[c][my];
        const double dy = static_cast<double>(my) - m_px / 2;
        straddles |= dx * dx + dy * dy <= core_radius_display_px * core_radius_display_px;
        out[my] = straddles ? 1 : 0;
      }
    }
  });
  refined_pixels_ = 0;
  for (const unsigned char straddles : straddles_) refined_pixels_ += straddles;
}

// The refined display pixels of totals_ summed from their PSF pixels, clamped (compute()).
void CpuFloatSpectralPsf::refine_straddles(const float* power) {
  const int n = settings_.grid_px, m_px = display_px_;
  const std::size_t plane = static_cast<std::size_t>(m_px) * m_px;
  std::vector<double>& total = totals_;
  // `total` is transposed: index x * M + y. Display rows on the threads; each display row's runs of
  // refined display pixels have their PSF pixels computed in one block (each run's PSF columns, side
  // by side, each once, in rows the loops over them vectorise along; per wavelength the row's
  // reference rows are read for all its runs while they are in cache), then each display pixel
  // sums its own PSF pixels clamped.
  parallel_chunks(m_px, settings_.threads, [&](int first, int last) {
    std::vector<float> block;
    std::vector<BlockSegment> segments;
    for (int my = first; my < last; ++my) {
      const auto& ys = box_[static_cast<std::size_t>(my)];
      const auto refined = [&](int mx) { return straddles_[static_cast<std::size_t>(mx) * m_px + my] != 0; };
      segments.clear();
      int width = 0;
      for (int run_start = 0; run_start < m_px;) {
        if (!refined(run_start)) {
          ++run_start;
          continue;
        }
        int run_end = run_start;
        int lowest = n, highest = -1;
        for (; run_end < m_px && refined(run_end); ++run_end)
          for (const PsfOverlap& overlap : box_[static_cast<std::size_t>(run_end)])
            lowest = std::min(lowest, overlap.input), highest = std::max(highest, overlap.input);
        // Rounded up to whole vectors of 8 where the grid has the columns: the columns past the
        // run are computed and not read, in place of the interpolation's one-by-one tail.
        const int columns = std::min(n - lowest, (highest - lowest + 1 + 7) / 8 * 8);
        segments.push_back({lowest, columns, width, run_start, run_end});
        width += columns;
        run_start = run_end;
      }
      if (segments.empty()) continue;
      spectral_block(power, segments, width, ys, block);
      const std::size_t stride = static_cast<std::size_t>(width), rows = ys.size();
      for (const BlockSegment& segment : segments)
        for (int mx = segment.first_display; mx < segment.end_display; ++mx) {
          const auto& xs = box_[static_cast<std::size_t>(mx)];
          double sum[3] = {0.0, 0.0, 0.0};
          for (std::size_t j = 0; j < rows; ++j)
            for (const PsfOverlap& x : xs) {
              const double area = x.fraction * ys[j].fraction;
              const std::size_t at = j * stride + static_cast<std::size_t>(segment.offset + x.input - segment.first_column);
              for (std::size_t c = 0; c < 3; ++c)
                sum[c] += area * std::max(0.0, static_cast<double>(block[c * rows * stride + at]));
            }
          for (int c = 0; c < 3; ++c) total[c * plane + static_cast<std::size_t>(mx) * m_px + my] = sum[c];
        }
    }
  });
}

Psf CpuFloatSpectralPsf::compute(const float* power, double pupil_diameter_mm) {
  if (!(pupil_diameter_mm > 0.0)) throw std::invalid_argument("glare/cpu/float_spectral_psf: pupil diameter must be > 0 mm");
  // `power` is column-major (CpuFloatPsf's layout): its rows are the PSF's columns. Every step below
  // treats the two axes alike (one W and one box for both, the screen and the core disk symmetric),
  // so it is written as for a row-major PSF: "rows", "y" and "display rows" are the input's rows
  // (PSF columns), and `total` comes out holding the row-major display PSF, which the last step
  // copies as it is.
  add_spectral_tiles(power);
  screen_straddles(pupil_diameter_mm);
  refine_straddles(power);

  const int m_px = display_px_;
  const std::size_t plane = static_cast<std::size_t>(m_px) * m_px;
  const std::vector<double>& total = totals_;
  Psf psf;
  psf.size_px = m_px;
  psf.channels = 3;
  psf.degrees_per_pixel = settings_.display_degrees_per_pixel;
  psf.values.assign(3 * plane, 0.0);
  for (int c = 0; c < 3; ++c) {
    double positive = 0.0;
    // total[c plane + x' M + y'] with x' the input's column, y' its row: PSF pixel (x, y) = (y', x')
    // at [y M + x], as Psf::at holds it.
    for (std::size_t k = 0; k < plane; ++k) {
      const double value = std::max(0.0, total[c * plane + k]);
      positive += value;
      psf.values[c * plane + k] = value;
    }
    if (!(positive > 0.0)) throw std::runtime_error("glare/cpu/float_spectral_psf: a Rec.709 channel has no positive energy");
    const double inverse = 1.0 / positive;
    for (std::size_t k = 0; k < plane; ++k) psf.values[c * plane + k] *= inverse;
  }
  return psf;
}

}  // namespace glarelab

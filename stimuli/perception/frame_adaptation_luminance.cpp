#include "stimuli/perception/frame_adaptation_luminance.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "core/parallel_for.h"

namespace glarelab {
namespace {

// One output sample's input pixels and their overlap (in input pixels) along one axis.
struct AxisTap {
  int index;
  double weight;
};

// Area resampling along one axis: output pixel o covers [o * n_in / n_out, (o + 1) * n_in / n_out)
// in input pixels; every input pixel contributes the length it shares with that span, divided by
// the span's length. Rows of weights sum to 1. An output's taps are the input pixels first..last
// in order, each with an overlap > 0 (the span starts inside `first` and ends inside `last`).
std::vector<std::vector<AxisTap>> area_taps(int n_in, int n_out) {
  std::vector<std::vector<AxisTap>> taps(static_cast<std::size_t>(n_out));
  const double scale = static_cast<double>(n_in) / n_out;
  for (int o = 0; o < n_out; ++o) {
    const double begin = o * scale, end = (o + 1) * scale;
    const int first = static_cast<int>(std::floor(begin));
    const int last = std::min(n_in - 1, static_cast<int>(std::ceil(end)) - 1);
    for (int i = first; i <= last; ++i) {
      const double overlap = std::min(end, i + 1.0) - std::max(begin, static_cast<double>(i));
      if (overlap > 0.0) taps[static_cast<std::size_t>(o)].push_back({i, overlap / scale});
    }
  }
  return taps;
}

// The second half of resample_plane: rows already resampled to `size` columns (height x size),
// resampled along y to size x size.
std::vector<double> resample_columns(const std::vector<double>& rows, int height, int size) {
  const auto y_taps = area_taps(height, size);
  std::vector<double> out(static_cast<std::size_t>(size) * size, 0.0);
  for (int o = 0; o < size; ++o)
    for (const AxisTap& tap : y_taps[static_cast<std::size_t>(o)])
      for (int x = 0; x < size; ++x)
        out[static_cast<std::size_t>(o) * size + x] += tap.weight * rows[static_cast<std::size_t>(tap.index) * size + x];
  return out;
}

// A plane (width x height) resampled to size x size by exact area overlap.
std::vector<double> resample_plane(const std::vector<double>& plane, int width, int height, int size) {
  const auto x_taps = area_taps(width, size);
  std::vector<double> rows(static_cast<std::size_t>(height) * size, 0.0);
  for (int y = 0; y < height; ++y)
    for (int o = 0; o < size; ++o) {
      double sum = 0.0;
      for (const AxisTap& tap : x_taps[static_cast<std::size_t>(o)])
        sum += tap.weight * plane[static_cast<std::size_t>(y) * width + tap.index];
      rows[static_cast<std::size_t>(y) * size + o] = sum;
    }
  return resample_columns(rows, height, size);
}

// One pyramid step: the 5-tap binomial filter [1 4 6 4 1] / 16 in x and y (edges clamped), then
// every second sample.
std::vector<double> pyramid_reduce(const std::vector<double>& plane, int size) {
  static constexpr double kBinomial[5] = {1.0 / 16, 4.0 / 16, 6.0 / 16, 4.0 / 16, 1.0 / 16};
  const int half = size / 2;
  auto at = [size](int i) { return std::clamp(i, 0, size - 1); };
  std::vector<double> rows(static_cast<std::size_t>(size) * half, 0.0);
  for (int y = 0; y < size; ++y)
    for (int o = 0; o < half; ++o) {
      double sum = 0.0;
      for (int k = -2; k <= 2; ++k) sum += kBinomial[k + 2] * plane[static_cast<std::size_t>(y) * size + at(2 * o + k)];
      rows[static_cast<std::size_t>(y) * half + o] = sum;
    }
  std::vector<double> out(static_cast<std::size_t>(half) * half, 0.0);
  for (int o = 0; o < half; ++o)
    for (int x = 0; x < half; ++x) {
      double sum = 0.0;
      for (int k = -2; k <= 2; ++k) sum += kBinomial[k + 2] * rows[static_cast<std::size_t>(at(2 * o + k)) * half + x];
      out[static_cast<std::size_t>(o) * half + x] = sum;
    }
  return out;
}

// The pyramid from the resampled size x size plane to the top level, averaged.
double pyramid_mean(std::vector<double> plane, const AdaptationWeighting& weighting) {
  int level = weighting.resampled_size_px;
  while (level > weighting.top_level_size_px) {
    plane = pyramid_reduce(plane, level);
    level /= 2;
  }
  double sum = 0.0;
  for (double v : plane) sum += v;
  return sum / static_cast<double>(plane.size());
}

double reduce_to_mean(const std::vector<double>& plane, int width, int height, const AdaptationWeighting& weighting) {
  return pyramid_mean(resample_plane(plane, width, height, weighting.resampled_size_px), weighting);
}

void check_adaptation_inputs(const ImageRGBA& frame, double gaze_x, double gaze_y, const AdaptationWeighting& weighting) {
  if (frame.empty()) throw std::invalid_argument("perception adaptation: the frame is empty");
  if (!std::isfinite(gaze_x) || !std::isfinite(gaze_y))
    throw std::invalid_argument("perception adaptation: gaze must be finite (got " + std::to_string(gaze_x) + ", " +
                                std::to_string(gaze_y) + ")");
  if (!std::isfinite(weighting.gaze_sigma_frame_widths) || weighting.gaze_sigma_frame_widths <= 0.0)
    throw std::invalid_argument("perception adaptation: gaze_sigma_frame_widths must be finite and > 0 (got " +
                                std::to_string(weighting.gaze_sigma_frame_widths) + ")");
  const int size = weighting.resampled_size_px, top = weighting.top_level_size_px;
  if (top < 1 || size < top || size % top != 0 || ((size / top) & (size / top - 1)) != 0)
    throw std::invalid_argument("perception adaptation: resampled_size_px / top_level_size_px must be a power of two");
}

// Eq. 5.1 of the taps' weighted sum, sum_k w_k Y(p_k) for taps [begin, end) of one row, in double:
// the weighted R, G and B summed first and Eq. 5.1 applied once, which is the same linear form (it
// differs from the reference's per-pixel order by double rounding, 1e-16 relative). The per-pixel
// luminance and its tap sum in double kept the stage at five times its floor, scalar; on SSE2 the
// pixel's four floats go to doubles two at a time and are summed two lanes at once, in two pairs of
// accumulators (the adds' latency). The sums stay in double: the result is held to 1e-12 of the
// reference (tests/perception_float_test.cpp), beyond a float sum's reach.
double weighted_luminance_sum(const float* row, const int* tap_index, const double* tap_weight, int begin, int end) {
  double red = 0.0, green = 0.0, blue = 0.0;
  int k = begin;
#if defined(__SSE2__)
  // area_taps' pixels of one output run contiguously from the first, so they are stepped through
  // rather than looked up (checked: a gap would take the loop below).
  const bool contiguous = end > begin && tap_index[end - 1] - tap_index[begin] == end - 1 - begin;
  const float* p = row + 4 * static_cast<std::ptrdiff_t>(end > begin ? tap_index[begin] : 0);
  __m128d rg0 = _mm_setzero_pd(), ba0 = _mm_setzero_pd(), rg1 = _mm_setzero_pd(), ba1 = _mm_setzero_pd();
  for (; contiguous && k + 2 <= end; k += 2, p += 8) {
    const __m128 p0 = _mm_loadu_ps(p), p1 = _mm_loadu_ps(p + 4);
    const __m128d w0 = _mm_set1_pd(tap_weight[k]), w1 = _mm_set1_pd(tap_weight[k + 1]);
    rg0 = _mm_add_pd(rg0, _mm_mul_pd(w0, _mm_cvtps_pd(p0)));
    ba0 = _mm_add_pd(ba0, _mm_mul_pd(w0, _mm_cvtps_pd(_mm_movehl_ps(p0, p0))));
    rg1 = _mm_add_pd(rg1, _mm_mul_pd(w1, _mm_cvtps_pd(p1)));
    ba1 = _mm_add_pd(ba1, _mm_mul_pd(w1, _mm_cvtps_pd(_mm_movehl_ps(p1, p1))));
  }
  const __m128d rg = _mm_add_pd(rg0, rg1), ba = _mm_add_pd(ba0, ba1);
  red = _mm_cvtsd_f64(rg);
  green = _mm_cvtsd_f64(_mm_unpackhi_pd(rg, rg));
  blue = _mm_cvtsd_f64(ba);
#endif
  for (; k < end; ++k) {
    const float* q = row + 4 * static_cast<std::ptrdiff_t>(tap_index[k]);
    red += tap_weight[k] * q[0];
    green += tap_weight[k] * q[1];
    blue += tap_weight[k] * q[2];
  }
  return luidolt_luminance_cd_m2(red, green, blue);
}

#if defined(__x86_64__) && defined(__GNUC__)
// The same sums with AVX2 and FMA, a whole row's outputs in one call: a pixel's four floats to four
// doubles in one conversion, its weight times them added in one fused step (one rounding where the
// SSE2 form has two), four accumulators for the adds' latency; each output's sums stored once and
// Eq. 5.1 applied to them (a call and the lanes' extraction per output cost as much as its pixels).
__attribute__((target("avx2,fma"))) void weighted_luminance_row_avx2(const float* row, const int* tap_begin,
                                                                     const int* tap_index, const double* tap_weight,
                                                                     int size, double* out) {
  for (int o = 0; o < size; ++o) {
    const int begin = tap_begin[o], end = tap_begin[o + 1];
    int k = begin;
    __m256d sum0 = _mm256_setzero_pd(), sum1 = _mm256_setzero_pd(), sum2 = _mm256_setzero_pd(), sum3 = _mm256_setzero_pd();
    if (end > begin && tap_index[end - 1] - tap_index[begin] == end - 1 - begin) {  // contiguous: stepped through
      const float* p = row + 4 * static_cast<std::ptrdiff_t>(tap_index[begin]);
      for (; k + 4 <= end; k += 4, p += 16) {
        sum0 = _mm256_fmadd_pd(_mm256_broadcast_sd(tap_weight + k), _mm256_cvtps_pd(_mm_loadu_ps(p)), sum0);
        sum1 = _mm256_fmadd_pd(_mm256_broadcast_sd(tap_weight + k + 1), _mm256_cvtps_pd(_mm_loadu_ps(p + 4)), sum1);
        sum2 = _mm256_fmadd_pd(_mm256_broadcast_sd(tap_weight + k + 2), _mm256_cvtps_pd(_mm_loadu_ps(p + 8)), sum2);
        sum3 = _mm256_fmadd_pd(_mm256_broadcast_sd(tap_weight + k + 3), _mm256_cvtps_pd(_mm_loadu_ps(p + 12)), sum3);
      }
    }
    sum0 = _mm256_add_pd(sum0, sum2);
    sum1 = _mm256_add_pd(sum1, sum3);
    for (; k < end; ++k) {
      const float* q = row + 4 * static_cast<std::ptrdiff_t>(tap_index[k]);
      sum1 = _mm256_fmadd_pd(_mm256_broadcast_sd(tap_weight + k), _mm256_cvtps_pd(_mm_loadu_ps(q)), sum1);
    }
    alignas(32) double rgba[4];
    _mm256_store_pd(rgba, _mm256_add_pd(sum0, sum1));
    out[o] = luidolt_luminance_cd_m2(rgba[0], rgba[1], rgba[2]);
  }
}
#endif

// Eq. 5.1 of each output's weighted sum along one row, out[0 .. size).
void weighted_luminance_row(VectorIsa isa, const float* row, const int* tap_begin, const int* tap_index,
                            const double* tap_weight, int size, double* out) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (isa == VectorIsa::avx2_fma) {
    weighted_luminance_row_avx2(row, tap_begin, tap_index, tap_weight, size, out);
    return;
  }
#else
  (void)isa;
#endif
  for (int o = 0; o < size; ++o) out[o] = weighted_luminance_sum(row, tap_index, tap_weight, tap_begin[o], tap_begin[o + 1]);
}

}  // namespace

double gaze_adaptation_weight(int x, int y, int width_px, int height_px, double gaze_x, double gaze_y,
                              double sigma_frame_widths) {
  // Distances in frame widths in both directions, so the Gaussian is circular on the screen.
  const double dx = ((x + 0.5) / width_px - gaze_x);
  const double dy = ((y + 0.5) / height_px - gaze_y) * static_cast<double>(height_px) / width_px;
  return std::exp(-(dx * dx + dy * dy) / (2.0 * sigma_frame_widths * sigma_frame_widths));
}

double frame_adaptation_luminance_cd_m2(const ImageRGBA& frame, double gaze_x, double gaze_y,
                                        const AdaptationWeighting& weighting) {
  check_adaptation_inputs(frame, gaze_x, gaze_y, weighting);
  const int width = frame.width_px, height = frame.height_px;
  const std::size_t n = static_cast<std::size_t>(width) * height;
  std::vector<double> weighted(n), weights(n);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float* p = frame.pixel(x, y);
      const double w = gaze_adaptation_weight(x, y, width, height, gaze_x, gaze_y, weighting.gaze_sigma_frame_widths);
      const std::size_t i = static_cast<std::size_t>(y) * width + x;
      weights[i] = w;
      weighted[i] = w * luidolt_luminance_cd_m2(p[0], p[1], p[2]);
    }
  const double mean_weight = reduce_to_mean(std::move(weights), width, height, weighting);
  const double mean_weighted = reduce_to_mean(std::move(weighted), width, height, weighting);
  // A gaze far outside the frame can underflow every weight; the frame then has no centre of
  // attention and its plain mean is the best estimate.
  if (!(mean_weight > 0.0)) {
    AdaptationWeighting uniform = weighting;
    uniform.gaze_sigma_frame_widths = 1e300;
    return frame_adaptation_luminance_cd_m2(frame, 0.5, 0.5, uniform);
  }
  return mean_weighted / mean_weight;
}

double frame_adaptation_luminance_float_cd_m2(const ImageRGBA& frame, double gaze_x, double gaze_y,
                                              const AdaptationWeighting& weighting, int threads, VectorIsa isa) {
  check_adaptation_inputs(frame, gaze_x, gaze_y, weighting);
  if (!vector_isa_available(isa)) isa = VectorIsa::sse2;
  const int width = frame.width_px, height = frame.height_px, size = weighting.resampled_size_px;
  // The gaze Gaussian is separable, exp(-(dx^2 + dy^2) / 2 s^2) = exp(-dx^2 / 2 s^2) exp(-dy^2 / 2 s^2)
  // (gaze_adaptation_weight's distances), so a frame needs width + height exponentials, and the
  // weight plane's resampled rows are the row factor times the column factors' tap sums.
  const double two_sigma_sq = 2.0 * weighting.gaze_sigma_frame_widths * weighting.gaze_sigma_frame_widths;
  std::vector<double> column_weight(static_cast<std::size_t>(width)), row_weight(static_cast<std::size_t>(height));
  for (int x = 0; x < width; ++x) {
    const double dx = (x + 0.5) / width - gaze_x;
    column_weight[static_cast<std::size_t>(x)] = std::exp(-dx * dx / two_sigma_sq);
  }
  for (int y = 0; y < height; ++y) {
    const double dy = ((y + 0.5) / height - gaze_y) * static_cast<double>(height) / width;
    row_weight[static_cast<std::size_t>(y)] = std::exp(-dy * dy / two_sigma_sq);
  }
  // The x taps with the column factors folded in, flattened: output o's taps are
  // [tap_begin[o], tap_begin[o + 1]) of tap_index and tap_weight.
  const auto x_taps = area_taps(width, size);
  std::vector<int> tap_begin{0}, tap_index;
  std::vector<double> tap_weight, tap_total(static_cast<std::size_t>(size), 0.0);
  for (int o = 0; o < size; ++o) {
    for (const AxisTap& tap : x_taps[static_cast<std::size_t>(o)]) {
      tap_index.push_back(tap.index);
      tap_weight.push_back(tap.weight * column_weight[static_cast<std::size_t>(tap.index)]);
      tap_total[static_cast<std::size_t>(o)] += tap_weight.back();
    }
    tap_begin.push_back(static_cast<int>(tap_index.size()));
  }
  std::vector<double> weighted_rows(static_cast<std::size_t>(height) * size), weight_rows(weighted_rows.size());
  parallel_chunks(height, threads, [&](int first, int last) {
    for (int y = first; y < last; ++y) {
      const float* row = frame.pixel(0, y);
      const double w_y = row_weight[static_cast<std::size_t>(y)];
      double* weighted = &weighted_rows[static_cast<std::size_t>(y) * size];
      weighted_luminance_row(isa, row, tap_begin.data(), tap_index.data(), tap_weight.data(), size, weighted);
      for (int o = 0; o < size; ++o) {
        weighted[o] *= w_y;
        weight_rows[static_cast<std::size_t>(y) * size + o] = w_y * tap_total[static_cast<std::size_t>(o)];
      }
    }
  });
  const double mean_weight = pyramid_mean(resample_columns(weight_rows, height, size), weighting);
  const double mean_weighted = pyramid_mean(resample_columns(weighted_rows, height, size), weighting);
  if (!(mean_weight > 0.0)) {  // as frame_adaptation_luminance_cd_m2: every weight underflowed
    AdaptationWeighting uniform = weighting;
    uniform.gaze_sigma_frame_widths = 1e300;
    return frame_adaptation_luminance_float_cd_m2(frame, 0.5, 0.5, uniform, threads, isa);
  }
  return mean_weighted / mean_weight;
}

}  // namespace glarelab

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

// The resampling, the pyramid and the top level's mean are linear and act on each axis apart
// (resample_plane: Ry P Rx^T; pyramid_reduce: D P D^T; the mean: 1^T P 1 / top^2), so their
// composition is sum_y b_y sum_x a_x P(x, y) with a = Rx^T D^T ... D^T 1 / top and b alike along y:
// one weight per column and one per row. These are those weights for an axis of n_in pixels.
std::vector<double> axis_mean_weights(int n_in, const AdaptationWeighting& weighting) {
  static constexpr double kBinomial[5] = {1.0 / 16, 4.0 / 16, 6.0 / 16, 4.0 / 16, 1.0 / 16};
  const int size = weighting.resampled_size_px, top = weighting.top_level_size_px;
  std::vector<double> level(static_cast<std::size_t>(top), 1.0 / top);
  for (int n = top; n < size; n *= 2) {  // pyramid_reduce's step from 2n to n, transposed
    std::vector<double> finer(2 * static_cast<std::size_t>(n), 0.0);
    for (int o = 0; o < n; ++o)
      for (int k = -2; k <= 2; ++k)
        finer[static_cast<std::size_t>(std::clamp(2 * o + k, 0, 2 * n - 1))] += kBinomial[k + 2] * level[static_cast<std::size_t>(o)];
    level = std::move(finer);
  }
  const auto taps = area_taps(n_in, size);
  std::vector<double> weights(static_cast<std::size_t>(n_in), 0.0);
  for (int o = 0; o < size; ++o)
    for (const AxisTap& tap : taps[static_cast<std::size_t>(o)])
      weights[static_cast<std::size_t>(tap.index)] += tap.weight * level[static_cast<std::size_t>(o)];
  return weights;
}

// The row's weighted R, G and B, sum_x weight_x (R, G, B)(x), in double: each pixel read once, its
// four floats to doubles and added with its column's weight. The sums stay in double: the result is
// held to 1e-12 of the reference (tests/perception_float_test.cpp), beyond a float sum's reach.
// On SSE2 a pixel's four floats go to doubles two at a time, two pixels in flight (the adds' latency).
void weighted_row_rgb_sse2(const float* row, const double* weight, int width, double* rgb) {
  int x = 0;
  double red = 0.0, green = 0.0, blue = 0.0;
#if defined(__SSE2__)
  __m128d rg0 = _mm_setzero_pd(), ba0 = _mm_setzero_pd(), rg1 = _mm_setzero_pd(), ba1 = _mm_setzero_pd();
  for (; x + 2 <= width; x += 2) {
    const __m128 p0 = _mm_loadu_ps(row + 4 * x), p1 = _mm_loadu_ps(row + 4 * x + 4);
    const __m128d w0 = _mm_set1_pd(weight[x]), w1 = _mm_set1_pd(weight[x + 1]);
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
  for (; x < width; ++x) {
    const float* q = row + 4 * static_cast<std::ptrdiff_t>(x);
    red += weight[x] * q[0];
    green += weight[x] * q[1];
    blue += weight[x] * q[2];
  }
  rgb[0] = red;
  rgb[1] = green;
  rgb[2] = blue;
}

#if defined(__x86_64__) && defined(__GNUC__)
// The same sums with AVX2 and FMA: a pixel's four floats to four doubles in one conversion, its
// weight times them added in one fused step (one rounding where the SSE2 form has two), four
// pixels in flight.
__attribute__((target("avx2,fma"))) void weighted_row_rgb_avx2(const float* row, const double* weight, int width, double* rgb) {
  __m256d sum0 = _mm256_setzero_pd(), sum1 = _mm256_setzero_pd(), sum2 = _mm256_setzero_pd(), sum3 = _mm256_setzero_pd();
  int x = 0;
  for (; x + 4 <= width; x += 4) {
    const float* p = row + 4 * static_cast<std::ptrdiff_t>(x);
    sum0 = _mm256_fmadd_pd(_mm256_broadcast_sd(weight + x), _mm256_cvtps_pd(_mm_loadu_ps(p)), sum0);
    sum1 = _mm256_fmadd_pd(_mm256_broadcast_sd(weight + x + 1), _mm256_cvtps_pd(_mm_loadu_ps(p + 4)), sum1);
    sum2 = _mm256_fmadd_pd(_mm256_broadcast_sd(weight + x + 2), _mm256_cvtps_pd(_mm_loadu_ps(p + 8)), sum2);
    sum3 = _mm256_fmadd_pd(_mm256_broadcast_sd(weight + x + 3), _mm256_cvtps_pd(_mm_loadu_ps(p + 12)), sum3);
  }
  for (; x < width; ++x)
    sum0 = _mm256_fmadd_pd(_mm256_broadcast_sd(weight + x), _mm256_cvtps_pd(_mm_loadu_ps(row + 4 * static_cast<std::ptrdiff_t>(x))), sum0);
  alignas(32) double sums[4];
  _mm256_store_pd(sums, _mm256_add_pd(_mm256_add_pd(sum0, sum2), _mm256_add_pd(sum1, sum3)));
  rgb[0] = sums[0];
  rgb[1] = sums[1];
  rgb[2] = sums[2];
}
#endif

void weighted_row_rgb(VectorIsa isa, const float* row, const double* weight, int width, double* rgb) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (isa == VectorIsa::avx2_fma) {
    weighted_row_rgb_avx2(row, weight, width, rgb);
    return;
  }
#else
  (void)isa;
#endif
  weighted_row_rgb_sse2(row, weight, width, rgb);
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
  const int width = frame.width_px, height = frame.height_px;
  // The gaze Gaussian is separable, exp(-(dx^2 + dy^2) / 2 s^2) = exp(-dx^2 / 2 s^2) exp(-dy^2 / 2 s^2)
  // (gaze_adaptation_weight's distances), and so is the reduction to the mean (axis_mean_weights):
  // mean(w Y) = sum_y b_y w_y sum_x a_x w_x Y(x, y) and mean(w) = (sum_y b_y w_y) (sum_x a_x w_x), so
  // the frame is read once, each pixel taking one weight, the work of the streaming floor.
  const double two_sigma_sq = 2.0 * weighting.gaze_sigma_frame_widths * weighting.gaze_sigma_frame_widths;
  std::vector<double> column_weight = axis_mean_weights(width, weighting), row_weight = axis_mean_weights(height, weighting);
  double column_total = 0.0, row_total = 0.0;
  for (int x = 0; x < width; ++x) {
    const double dx = (x + 0.5) / width - gaze_x;
    column_weight[static_cast<std::size_t>(x)] *= std::exp(-dx * dx / two_sigma_sq);
    column_total += column_weight[static_cast<std::size_t>(x)];
  }
  for (int y = 0; y < height; ++y) {
    const double dy = ((y + 0.5) / height - gaze_y) * static_cast<double>(height) / width;
    row_weight[static_cast<std::size_t>(y)] *= std::exp(-dy * dy / two_sigma_sq);
    row_total += row_weight[static_cast<std::size_t>(y)];
  }
  // Each row's Eq. 5.1 of its weighted R, G and B, summed over the rows in order afterwards, so the
  // result does not depend on `threads`.
  std::vector<double> row_luminance(static_cast<std::size_t>(height));
  parallel_chunks(height, threads, [&](int first, int last) {
    for (int y = first; y < last; ++y) {
      double rgb[3];
      weighted_row_rgb(isa, frame.pixel(0, y), column_weight.data(), width, rgb);
      row_luminance[static_cast<std::size_t>(y)] = luidolt_luminance_cd_m2(rgb[0], rgb[1], rgb[2]);
    }
  });
  double mean_weighted = 0.0;
  for (int y = 0; y < height; ++y) mean_weighted += row_weight[static_cast<std::size_t>(y)] * row_luminance[static_cast<std::size_t>(y)];
  const double mean_weight = row_total * column_total;
  if (!(mean_weight > 0.0)) {  // as frame_adaptation_luminance_cd_m2: every weight underflowed
    AdaptationWeighting uniform = weighting;
    uniform.gaze_sigma_frame_widths = 1e300;
    return frame_adaptation_luminance_float_cd_m2(frame, 0.5, 0.5, uniform, threads, isa);
  }
  return mean_weighted / mean_weight;
}

}  // namespace glarelab

#include "stimuli/depth_of_field_blur.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "core/fft_size.h"
#include "core/parallel_for.h"
#include "glare/cpu/fftw_float_plan.h"

namespace glarelab {
namespace {

// Cost of one FFT point (per log2 of the padded size, per channel and both directions) against one
// multiply-add of the direct sum, from bench/depth_of_field_bench.cpp (BM_DepthLayerBlur*) on a
// 1024-wide layer, 2 threads: direct and FFT take the same time at about 100 nonzero taps (a circle
// of radius 5.5 px) both for the whole frame and for a 32-row band, which gives 4.6 to 5.5.
constexpr double kFftPointCost = 5.0;

struct Tap {
  int dx;
  float weight;
};

// The kernel's nonzero taps by row: direct convolution skips the zero corners of the ellipse.
std::vector<std::vector<Tap>> taps_by_row(const EllipticalKernel& kernel) {
  std::vector<std::vector<Tap>> rows(static_cast<std::size_t>(kernel.height()));
  for (int dy = -kernel.radius_y_px; dy <= kernel.radius_y_px; ++dy)
    for (int dx = -kernel.radius_x_px; dx <= kernel.radius_x_px; ++dx) {
      const double w = kernel.at(dx, dy);
      if (w != 0.0) rows[static_cast<std::size_t>(dy + kernel.radius_y_px)].push_back({dx, static_cast<float>(w)});
    }
  return rows;
}

// target += weight * source over `pixels` RGBA pixels. Written a pixel (four floats) at a time on
// non-aliasing pointers so that it vectorises at -O2 (superword parallelism, no loop versioning).
void add_scaled_row(float* __restrict target, const float* __restrict source, float weight, int pixels) {
  for (int x = 0; x < pixels; ++x, target += 4, source += 4) {
    target[0] += weight * source[0];
    target[1] += weight * source[1];
    target[2] += weight * source[2];
    target[3] += weight * source[3];
  }
}

#if defined(__x86_64__) && defined(__GNUC__)
// The same adds two pixels (eight floats) at a time: AVX2 without FMA, so each value is rounded
// after the product and after the sum, as above.
__attribute__((target("avx2"))) void add_scaled_row_avx2(float* __restrict target, const float* __restrict source, float weight,
                                                         int pixels) {
  const __m256 w = _mm256_set1_ps(weight);
  int x = 0;
  for (; x + 2 <= pixels; x += 2, target += 8, source += 8)
    _mm256_storeu_ps(target, _mm256_add_ps(_mm256_loadu_ps(target), _mm256_mul_ps(w, _mm256_loadu_ps(source))));
  if (x < pixels) add_scaled_row(target, source, weight, pixels - x);
}
#endif

// The direct sum's row adds in the form `isa` asks for.
void add_scaled_row(VectorIsa isa, float* __restrict target, const float* __restrict source, float weight, int pixels) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (isa == VectorIsa::avx2_fma) {
    add_scaled_row_avx2(target, source, weight, pixels);
    return;
  }
#else
  (void)isa;
#endif
  add_scaled_row(target, source, weight, pixels);
}

LayerImage grown_rectangle(const LayerImage& layer, const EllipticalKernel& kernel) {
  LayerImage out;
  out.x0_px = layer.x0_px - kernel.radius_x_px;
  out.y0_px = layer.y0_px - kernel.radius_y_px;
  out.width_px = layer.width_px + 2 * kernel.radius_x_px;
  out.height_px = layer.height_px + 2 * kernel.radius_y_px;
  out.rgba.assign(4 * static_cast<std::size_t>(out.width_px) * out.height_px, 0.0f);
  return out;
}

// out(o) = sum over taps d of w(d) in(o - d): output row oy gathers input rows oy - ry - dy; each
// tap adds a scaled copy of the input row's nonzero span (4 floats a pixel) at column offset
// rx + dx. Skipping the zeros around the span changes no value (adding w x 0 adds nothing), so the
// cost follows the layer's content, not its bounding rectangle (a diagonal band of a tilted plane).
LayerImage blur_direct(const LayerImage& layer, const std::vector<RowSpan>& spans, const EllipticalKernel& kernel,
                       int threads, VectorIsa isa) {
  LayerImage out = grown_rectangle(layer, kernel);
  const std::vector<std::vector<Tap>> rows = taps_by_row(kernel);
  parallel_chunks(out.height_px, threads, [&](int first, int last) {
    for (int oy = first; oy < last; ++oy) {
      float* out_row = out.pixel(0, oy);
      for (int dy = -kernel.radius_y_px; dy <= kernel.radius_y_px; ++dy) {
        const int sy = oy - kernel.radius_y_px - dy;
        if (sy < 0 || sy >= layer.height_px) continue;
        const RowSpan span = spans[static_cast<std::size_t>(sy)];
        if (span.first >= span.last) continue;
        const float* in_row = layer.pixel(span.first, sy);
        for (const Tap& tap : rows[static_cast<std::size_t>(dy + kernel.radius_y_px)]) {
          add_scaled_row(isa, out_row + 4 * static_cast<std::size_t>(kernel.radius_x_px + tap.dx + span.first), in_row,
                         tap.weight, span.last - span.first);
        }
      }
    }
  });
  return out;
}

// Linear convolution by circular convolution on a zero-padded grid at least as large as the output
// (so nothing wraps), the kernel's centre at the origin. One FFTW plan a channel, single-threaded:
// the channels run in parallel and each is computed the same way whatever the thread count.
LayerImage blur_fft(const LayerImage& layer, const EllipticalKernel& kernel, int threads) {
  LayerImage out = grown_rectangle(layer, kernel);
  const int rows = good_fft_size(out.height_px), cols = good_fft_size(out.width_px);
  const int spectrum_cols = cols / 2 + 1;
  const std::size_t real_size = static_cast<std::size_t>(rows) * cols;
  const std::size_t spectrum_size = static_cast<std::size_t>(rows) * spectrum_cols;

  FftwFloatBuffer<float> kernel_real(real_size);
  FftwFloatBuffer<std::complex<float>> kernel_spectrum(spectrum_size);
  for (int dy = -kernel.radius_y_px; dy <= kernel.radius_y_px; ++dy)
    for (int dx = -kernel.radius_x_px; dx <= kernel.radius_x_px; ++dx) {
      const std::size_t r = static_cast<std::size_t>((dy + rows) % rows),
                        c = static_cast<std::size_t>((dx + cols) % cols);
      kernel_real[r * static_cast<std::size_t>(cols) + c] = static_cast<float>(kernel.at(dx, dy));
    }
  FftwFloatPlan::real_forward(rows, cols, 1, kernel_real.data(), kernel_spectrum.data(), 1).execute();
  const float scale = 1.0f / static_cast<float>(real_size);

  parallel_chunks(4, threads, [&](int first, int last) {
    FftwFloatBuffer<float> real(real_size);
    FftwFloatBuffer<std::complex<float>> spectrum(spectrum_size);
    const FftwFloatPlan forward = FftwFloatPlan::real_forward(rows, cols, 1, real.data(), spectrum.data(), 1);
    const FftwFloatPlan inverse = FftwFloatPlan::real_inverse(rows, cols, 1, spectrum.data(), real.data(), 1);
    for (int channel = first; channel < last; ++channel) {
      std::fill(real.data(), real.data() + real_size, 0.0f);
      for (int y = 0; y < layer.height_px; ++y)
        for (int x = 0; x < layer.width_px; ++x)
          real[static_cast<std::size_t>(y) * cols + x] = layer.pixel(x, y)[channel];
      forward.execute();
      for (std::size_t k = 0; k < spectrum_size; ++k) spectrum[k] *= kernel_spectrum[k] * scale;
      inverse.execute();
      // Input pixel (x, y) sits at grid (x, y); output pixel (ox, oy) of the grown rectangle is
      // grid (ox - rx, oy - ry), negative indices wrapping to the far end.
      for (int oy = 0; oy < out.height_px; ++oy) {
        const int r = oy - kernel.radius_y_px < 0 ? oy - kernel.radius_y_px + rows : oy - kernel.radius_y_px;
        const float* grid_row = &real[static_cast<std::size_t>(r) * cols];
        float* out_row = out.pixel(0, oy) + channel;
        for (int ox = 0; ox < out.width_px; ++ox) {
          const int c = ox - kernel.radius_x_px < 0 ? ox - kernel.radius_x_px + cols : ox - kernel.radius_x_px;
          out_row[4 * static_cast<std::size_t>(ox)] = grid_row[c];
        }
      }
    }
  });
  return out;
}

}  // namespace

std::vector<RowSpan> nonzero_row_spans(const LayerImage& layer) {
  std::vector<RowSpan> spans(static_cast<std::size_t>(layer.height_px));
  for (int y = 0; y < layer.height_px; ++y) {
    const auto nonzero = [&](int x) {
      const float* p = layer.pixel(x, y);
      return p[0] != 0.0f || p[1] != 0.0f || p[2] != 0.0f || p[3] != 0.0f;
    };
    int first = 0, last = layer.width_px;
    while (first < last && !nonzero(first)) ++first;
    while (last > first && !nonzero(last - 1)) --last;
    spans[static_cast<std::size_t>(y)] = {first, last};
  }
  return spans;
}

std::vector<RowSpan> blurred_row_spans(const std::vector<RowSpan>& spans, const EllipticalKernel& kernel) {
  const int rows = static_cast<int>(spans.size()) + 2 * kernel.radius_y_px;
  std::vector<RowSpan> grown(static_cast<std::size_t>(rows));
  for (int oy = 0; oy < rows; ++oy) {
    RowSpan span{std::numeric_limits<int>::max(), std::numeric_limits<int>::min()};
    for (int sy = std::max(0, oy - 2 * kernel.radius_y_px); sy <= std::min(oy, static_cast<int>(spans.size()) - 1);
         ++sy) {
      const RowSpan& in = spans[static_cast<std::size_t>(sy)];
      if (in.first >= in.last) continue;
      span.first = std::min(span.first, in.first);
      span.last = std::max(span.last, in.last + 2 * kernel.radius_x_px);
    }
    if (span.first < span.last) grown[static_cast<std::size_t>(oy)] = span;
  }
  return grown;
}

LayerImage blur_layer(const LayerImage& layer, const std::vector<RowSpan>& spans, const EllipticalKernel& kernel,
                      LayerConvolution method, int threads, VectorIsa isa) {
  if (spans.size() != static_cast<std::size_t>(layer.height_px))
    throw std::invalid_argument("stimuli/depth_of_field_blur: " + std::to_string(spans.size()) + " row spans for a " +
                                std::to_string(layer.height_px) + "-row layer");
  if (!vector_isa_available(isa)) isa = VectorIsa::sse2;
  return method == LayerConvolution::direct ? blur_direct(layer, spans, kernel, threads, isa)
                                            : blur_fft(layer, kernel, threads);
}

LayerConvolution cheaper_layer_convolution(const LayerImage& layer, const std::vector<RowSpan>& spans,
                                           const EllipticalKernel& kernel) {
  double content_px = 0.0;
  for (const RowSpan& span : spans) content_px += span.last - span.first;
  const double direct_cost = 4.0 * content_px * kernel.nonzero_taps();
  const double rows = good_fft_size(layer.height_px + 2 * kernel.radius_y_px);
  const double cols = good_fft_size(layer.width_px + 2 * kernel.radius_x_px);
  // Four channels, each a forward and an inverse real transform (half a complex one each).
  const double fft_cost = kFftPointCost * 4.0 * rows * cols * std::log2(rows * cols);
  return direct_cost <= fft_cost ? LayerConvolution::direct : LayerConvolution::fft;
}

}  // namespace glarelab

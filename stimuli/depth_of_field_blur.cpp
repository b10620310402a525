#include "stimuli/depth_of_field_blur.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/fft_size.h"
#include "core/parallel_for.h"
#include "glare/cpu/fftw_float_plan.h"
#include "stimuli/depth_of_field_rows.h"

namespace glarelab {
namespace {

// Cost of one FFT point (per log2 of the padded size, per channel and both directions) against one
// multiply-add of the direct sum, from blur_layer both ways on a 1024-wide layer, 2 threads, the
// process' CPU time (docs/DEPTH_OF_FIELD.md, section 4). The SSE2 and AVX2 forms: direct and FFT
// take the same time at about 320 nonzero taps (a circle of radius 10 px) for the whole frame and
// about 550 (13 px) for a 32-row band, which gives 15 to 18 (it was 5, the crossover at 100 taps,
// with the tap-by-tap row adds). The AVX-512 form (its loads shared by eight registers, about 2.3
// times the AVX2 form's speed): about 850 taps (16 px) for the frame and 1,700 (23 px) for the band,
// which gives 39 for both.
constexpr double kFftPointCost = 16.0;
constexpr double kFftPointCostAvx512 = 40.0;

LayerImage grown_rectangle(const LayerImage& layer, const EllipticalKernel& kernel) {
  LayerImage out;
  out.x0_px = layer.x0_px - kernel.radius_x_px;
  out.y0_px = layer.y0_px - kernel.radius_y_px;
  out.width_px = layer.width_px + 2 * kernel.radius_x_px;
  out.height_px = layer.height_px + 2 * kernel.radius_y_px;
  out.rgba.assign(4 * static_cast<std::size_t>(out.width_px) * out.height_px, 0.0f);
  return out;
}

// A blur (direct or FFT, on rows) written into the blurred rectangle.
LayerImage blur_into_rectangle(const LayerImage& layer, const std::vector<RowSpan>& spans,
                               const EllipticalKernel& kernel, LayerConvolution method, int threads, VectorIsa isa) {
  LayerImage out = grown_rectangle(layer, kernel);
  LayerRows rows;
  copy_layer_rows(layer, spans, kernel, rows);
  const BlurredRowSink write = [&](int row, int first, int count, const float* rgba) {
    std::copy_n(rgba, 4 * static_cast<std::size_t>(count), out.pixel(first, row));
  };
  if (method == LayerConvolution::direct)
    blur_rows_direct(rows, kernel, threads, isa, write);
  else {
    LayerFftBuffers buffers;
    blur_rows_fft(rows, kernel, threads, write, buffers);
  }
  return out;
}

}  // namespace

// Linear convolution by circular convolution on a zero-padded grid at least as large as the output
// (so nothing wraps), the kernel's centre at the origin. A grid a channel (zeroed when made, the
// rows' spans copied in) and one FFTW plan pair a channel, single-threaded: the channels run in
// parallel and each is computed the same way whatever the thread count. The output rows are then
// read from the four grids on blurred_row_spans(rows.spans).
void blur_rows_fft(const LayerRows& layer, const EllipticalKernel& kernel, int threads, const BlurredRowSink& sink,
                   LayerFftBuffers& buffers) {
  const int out_height = layer.height_px + 2 * kernel.radius_y_px, out_width = layer.width_px + 2 * kernel.radius_x_px;
  const int rows = good_fft_size(out_height), cols = good_fft_size(out_width);
  const int spectrum_cols = cols / 2 + 1;
  const std::size_t real_size = static_cast<std::size_t>(rows) * cols;
  const std::size_t spectrum_size = static_cast<std::size_t>(rows) * spectrum_cols;
  if (buffers.rows != rows || buffers.cols != cols) {
    buffers = LayerFftBuffers{};
    for (int channel = 0; channel < 4; ++channel) {
      buffers.grids.emplace_back(real_size);
      buffers.spectra.emplace_back(spectrum_size);
    }
    buffers.kernel_real = FftwFloatBuffer<float>(real_size);
    buffers.kernel_spectrum = FftwFloatBuffer<std::complex<float>>(spectrum_size);
    buffers.rows = rows;
    buffers.cols = cols;
  } else {
    for (FftwFloatBuffer<float>& grid : buffers.grids) std::fill(grid.data(), grid.data() + real_size, 0.0f);
    std::fill(buffers.kernel_real.data(), buffers.kernel_real.data() + real_size, 0.0f);
  }
  const FftwFloatBuffer<std::complex<float>>& kernel_spectrum = buffers.kernel_spectrum;
  for (int dy = -kernel.radius_y_px; dy <= kernel.radius_y_px; ++dy)
    for (int dx = -kernel.radius_x_px; dx <= kernel.radius_x_px; ++dx) {
      const std::size_t r = static_cast<std::size_t>((dy + rows) % rows),
                        c = static_cast<std::size_t>((dx + cols) % cols);
      buffers.kernel_real[r * static_cast<std::size_t>(cols) + c] = static_cast<float>(kernel.at(dx, dy));
    }
  FftwFloatPlan::real_forward(rows, cols, 1, buffers.kernel_real.data(), buffers.kernel_spectrum.data(), 1).execute();
  const float scale = 1.0f / static_cast<float>(real_size);

  std::vector<FftwFloatBuffer<float>>& grids = buffers.grids;
  parallel_chunks(4, threads, [&](int first, int last) {
    for (int channel = first; channel < last; ++channel) {
      float* real = grids[static_cast<std::size_t>(channel)].data();
      FftwFloatBuffer<std::complex<float>>& spectrum = buffers.spectra[static_cast<std::size_t>(channel)];
      const FftwFloatPlan forward = FftwFloatPlan::real_forward(rows, cols, 1, real, spectrum.data(), 1);
      const FftwFloatPlan inverse = FftwFloatPlan::real_inverse(rows, cols, 1, spectrum.data(), real, 1);
      for (int y = 0; y < layer.height_px; ++y) {
        float* grid_row = real + static_cast<std::size_t>(y) * cols;
        for (std::size_t s = layer.first_segment[static_cast<std::size_t>(y)];
             s < layer.first_segment[static_cast<std::size_t>(y) + 1]; ++s) {
          const RowSpan& segment = layer.segments[s];
          const float* in = layer.segment_pixels(s);
          for (int x = segment.first; x < segment.last; ++x)
            grid_row[x] = in[4 * static_cast<std::size_t>(x - segment.first) + channel];
        }
      }
      forward.execute();
      for (std::size_t k = 0; k < spectrum_size; ++k) spectrum[k] *= kernel_spectrum[k] * scale;
      inverse.execute();
    }
  });
  // Input pixel (x, y) sits at grid (x, y); output pixel (ox, oy) of the grown rectangle is grid
  // (ox - rx, oy - ry), negative indices wrapping to the far end.
  const std::vector<RowSpan> out_spans = blurred_row_spans(layer.spans, kernel);
  parallel_chunks(out_height, threads, [&](int first, int last) {
    std::vector<float> out;
    for (int oy = first; oy < last; ++oy) {
      const RowSpan& span = out_spans[static_cast<std::size_t>(oy)];
      if (span.first >= span.last) continue;
      const int r = oy - kernel.radius_y_px < 0 ? oy - kernel.radius_y_px + rows : oy - kernel.radius_y_px;
      out.resize(4 * static_cast<std::size_t>(span.last - span.first));
      for (int channel = 0; channel < 4; ++channel) {
        const float* grid_row = grids[static_cast<std::size_t>(channel)].data() + static_cast<std::size_t>(r) * cols;
        for (int ox = span.first; ox < span.last; ++ox) {
          const int c = ox - kernel.radius_x_px < 0 ? ox - kernel.radius_x_px + cols : ox - kernel.radius_x_px;
          out[4 * static_cast<std::size_t>(ox - span.first) + static_cast<std::size_t>(channel)] = grid_row[c];
        }
      }
      sink(oy, span.first, span.last - span.first, out.data());
    }
  });
}

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
  return blur_into_rectangle(layer, spans, kernel, method, threads, isa);
}

LayerConvolution cheaper_layer_convolution(int width_px, int height_px, const std::vector<RowSpan>& spans,
                                           const EllipticalKernel& kernel, VectorIsa isa) {
  double content_px = 0.0;
  for (const RowSpan& span : spans) content_px += span.last - span.first;
  const double direct_cost = 4.0 * content_px * kernel.nonzero_taps();
  const double rows = good_fft_size(height_px + 2 * kernel.radius_y_px);
  const double cols = good_fft_size(width_px + 2 * kernel.radius_x_px);
  // Four channels, each a forward and an inverse real transform (half a complex one each).
  const double point_cost =
      isa == VectorIsa::avx512 && vector_isa_available(VectorIsa::avx512) ? kFftPointCostAvx512 : kFftPointCost;
  const double fft_cost = point_cost * 4.0 * rows * cols * std::log2(rows * cols);
  return direct_cost <= fft_cost ? LayerConvolution::direct : LayerConvolution::fft;
}

LayerConvolution cheaper_layer_convolution(const LayerImage& layer, const std::vector<RowSpan>& spans,
                                           const EllipticalKernel& kernel, VectorIsa isa) {
  return cheaper_layer_convolution(layer.width_px, layer.height_px, spans, kernel, isa);
}

}  // namespace glarelab

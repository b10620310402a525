#pragma once
// One depth layer blurred by its elliptical kernel (stimuli/elliptical_kernel.h): premultiplied
// RGBA (colour times coverage, coverage in alpha), so that the blurred alpha says how much of each
// pixel the layer's blurred surface covers (Porter and Duff 1984) and the layers can be composited.
//
// Two ways to the same linear convolution, both on the layer's rows (stimuli/depth_of_field_rows.h):
// direct (each output gathers the kernel's nonzero taps from the rows' nonzero spans: cost ~ the
// layer's pixels x nonzero taps) and by FFT (FFTW float, zero-padded so nothing wraps: cost ~
// padded area x log of it, whatever the kernel). Which is faster depends on the kernel's area
// against the log of the layer's; docs/DEPTH_OF_FIELD.md has the measured crossover,
// cheaper_layer_convolution the rule drawn from it. blur_layer is the convolution of a rectangle
// (the tests' and the bench's); the stage blurs rows and adds them into the frame as they come.
#include <vector>

#include "core/vector_isa.h"
#include "stimuli/elliptical_kernel.h"

namespace glarelab {

// Premultiplied RGBA on the rectangle [x0, x0 + width) x [y0, y0 + height) of the frame.
struct LayerImage {
  int x0_px = 0, y0_px = 0;
  int width_px = 0, height_px = 0;
  std::vector<float> rgba;  // 4 * width_px * height_px, row-major, row 0 at the top
  float* pixel(int x, int y) { return &rgba[4 * (static_cast<std::size_t>(y) * width_px + x)]; }
  const float* pixel(int x, int y) const { return &rgba[4 * (static_cast<std::size_t>(y) * width_px + x)]; }
};

// The pixels [first, last) of a layer's row outside which every value is zero (first == last: none).
struct RowSpan {
  int first = 0, last = 0;
};
std::vector<RowSpan> nonzero_row_spans(const LayerImage& layer);

// Spans of the blurred layer (on blur_layer's grown rectangle) outside which it is zero, from the
// input's spans: output row oy gathers input rows oy - 2 ry .. oy, each reaching 2 rx columns on.
std::vector<RowSpan> blurred_row_spans(const std::vector<RowSpan>& spans, const EllipticalKernel& kernel);

enum class LayerConvolution { direct, fft };

// The layer convolved with the kernel, on the layer's rectangle grown by the kernel's radii (it may
// reach outside the frame; the caller clips). Rows (direct) or colour channels (FFT) are split over
// `threads`; each output value is computed by the same operations in the same order whatever the
// thread count, so the result does not depend on it.
// `spans`: nonzero_row_spans(layer), or any spans outside which the layer is zero.
// `isa`: the form of the direct sum (core/vector_isa.h, depth_of_field_rows.h): SSE2 rounds each
// product and each sum; AVX2 and AVX-512 add each product by a fused multiply-add, AVX-512 in
// another order (each form within the bound derived in depth_of_field_rows.h of the others); one
// this CPU does not run takes SSE2. Outside the blurred rows' spans the rectangle is 0.
LayerImage blur_layer(const LayerImage& layer, const std::vector<RowSpan>& spans, const EllipticalKernel& kernel,
                      LayerConvolution method, int threads, VectorIsa isa = widest_vector_isa_with_avx512());
inline LayerImage blur_layer(const LayerImage& layer, const EllipticalKernel& kernel, LayerConvolution method,
                             int threads, VectorIsa isa = widest_vector_isa_with_avx512()) {
  return blur_layer(layer, nonzero_row_spans(layer), kernel, method, threads, isa);
}

// The method expected to be faster for this layer and kernel with the direct sum in form `isa`
// (one this CPU does not run: SSE2, as blur_layer takes it): direct costs its rows' nonzero spans
// times the kernel's nonzero taps, the FFT its padded rectangle times the log of its size (the
// constant between them measured for each form, docs/DEPTH_OF_FIELD.md, section 4).
LayerConvolution cheaper_layer_convolution(int width_px, int height_px, const std::vector<RowSpan>& spans,
                                           const EllipticalKernel& kernel,
                                           VectorIsa isa = widest_vector_isa_with_avx512());
LayerConvolution cheaper_layer_convolution(const LayerImage& layer, const std::vector<RowSpan>& spans,
                                           const EllipticalKernel& kernel,
                                           VectorIsa isa = widest_vector_isa_with_avx512());
inline LayerConvolution cheaper_layer_convolution(const LayerImage& layer, const EllipticalKernel& kernel,
                                                  VectorIsa isa = widest_vector_isa_with_avx512()) {
  return cheaper_layer_convolution(layer, nonzero_row_spans(layer), kernel, isa);
}

}  // namespace glarelab

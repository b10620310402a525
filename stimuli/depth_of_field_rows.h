#pragma once
// A depth layer's pixels kept row by row on their spans (stimuli/depth_of_field_blur.h), and the
// direct sum of the layer's blur computed from them one output row at a time.
//
// Why rows. A layer's rectangle reaches across the frame (a slice of a receding floor beside a
// board far to its side), but its pixels are a band: held as a rectangle, every layer of a frame
// would pay a frame-sized zero fill and, above glibc's mmap threshold, fresh page faults for its
// image and again for its blurred rectangle. Here each row holds only its span, padded with zeros, in
// one buffer the caller keeps from layer to layer; the blurred rows go to the caller one at a time
// (added into the frame's sum, their coverage kept for occlusion) and are never stored as an image.
//
// The sum. Each output pixel gathers the kernel's nonzero taps (rows top to bottom) from the input
// rows, sixteen pixels at a time held in registers (eight with SSE2, thirty-two with AVX-512): the
// output is written once instead of read and written once a tap, which would make the sum
// memory-bound. The forms (core/vector_isa.h):
// - sse2: each row's taps left to right, each product and each sum rounded once: the bits of a sum
//   of whole rows tap by tap (the pads add w x 0 = +0, which changes no sum);
// - avx2_fma: the same order, each product added by a fused multiply-add (one rounding);
// - avx512: fused multiply-adds, each row's taps by their offset modulo 4 (the pixels of a
//   register), so that the block's registers share each input vector (one load a tap, not eight).
// Each form gives every output the same bits whatever the thread count and whatever block or span
// split the row (an output's products are always added in its form's order).
//
// The bound between forms. An output is S = sum of T products p_i = w_i x_i >= 0 (T the kernel's
// nonzero taps at most; weights and premultiplied values are non-negative), added in some order
// from +0 in float (unit roundoff u = 2^-24). In SSE2 each product is rounded and each addition
// after the first (0 + p is exact) is rounded: a term sees its product's rounding and the additions
// from its own to the last, at most T roundings; with a fused multiply-add a term sees the additions
// from its own to the last, at most T too, in any order. So each form's value is
// sum p_i (1 + theta_i) with |theta_i| <= gamma_T = T u / (1 - T u) (Higham, Accuracy and Stability
// of Numerical Algorithms, 2nd ed., Lemma 3.1), within gamma_T S of S since every p_i >= 0, and two
// forms differ by at most 2 gamma_T S <= 2 gamma_T s / (1 - gamma_T), s either form's value (test
// DirectAndFftConvolutionAgreeAndAreThreadInvariant). For a kernel 101 taps wide (at most about
// 8,000 taps) that is under 1e-3 relative at worst; rounding errors of either sign mostly cancel, and
// the measured differences are far below it (docs/PERFORMANCE.md: at most 7.6e-7 relative on the
// whole-frame bench).
#include <complex>
#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

#include "core/vector_isa.h"
#include "glare/cpu/fftw_float_plan.h"
#include "stimuli/depth_of_field_blur.h"
#include "stimuli/elliptical_kernel.h"

namespace glarelab {

// Pixels the direct sum computes at once (its block); rows are padded by 2 radius_x + this.
inline constexpr int kDirectBlockPx = 16;

// A layer's rectangle as LayerImage places it, and each row's segments of premultiplied RGBA: the
// stretches of the row that hold the layer's pixels (a board's row beside a gap and another board),
// each stored with pad_px zero pixels on either side.
struct LayerRows {
  int x0_px = 0, y0_px = 0;
  int width_px = 0, height_px = 0;
  int pad_px = 0;                          // zero pixels stored on each side of a segment
  std::vector<RowSpan> spans;              // a row's hull: its first segment's first pixel to its last one's end
  std::vector<std::size_t> first_segment;  // row y's segments: [first_segment[y], first_segment[y + 1])
  std::vector<RowSpan> segments;           // rectangle columns, left to right, none empty
  std::vector<std::size_t> offsets;        // a segment's first stored float (column first - pad_px)

  // Room for `floats` values without filling it (lay_out grows it as needed; reserving the
  // largest layer's size first spares the copies of growing).
  void reserve(std::size_t floats);

  // Sets the rectangle and the segments, one a row (`row_spans`; an empty span: none), with the
  // padding for `kernel`, and lays them out: each segment's pads are zeroed and its pixels left for
  // the caller to write through segment_pixels.
  void lay_out(int x0, int y0, int width, int height, const std::vector<RowSpan>& row_spans,
               const EllipticalKernel& kernel);
  // The same with several segments a row (`row_first`, height + 1 entries, indexing `row_segments`);
  // two segments of a row must lie at least min_segment_gap_px(kernel) apart, so that no block of
  // the direct sum reads both and each output adds its products in the order of one span a row.
  void lay_out_segments(int x0, int y0, int width, int height, const std::vector<std::size_t>& row_first,
                        const std::vector<RowSpan>& row_segments, const EllipticalKernel& kernel);
  // The first pixel of segment s (4 floats a pixel), writable.
  float* segment_pixels(std::size_t s) { return segment_start(s) + 4 * static_cast<std::size_t>(pad_px); }
  const float* segment_pixels(std::size_t s) const { return segment_start(s) + 4 * static_cast<std::size_t>(pad_px); }
  // Segment s's stored floats, from its left pad.
  float* segment_start(std::size_t s) { return storage_.get() + offsets[s]; }
  const float* segment_start(std::size_t s) const { return storage_.get() + offsets[s]; }

 private:
  // Kept between layers: grown, never shrunk, never filled as a whole.
  std::unique_ptr<float[]> storage_;
  std::size_t capacity_ = 0;
};

// Segments of a row closer than this (2 radius_x + the block) are one segment, zeros between.
int min_segment_gap_px(const EllipticalKernel& kernel);

// The rows of `layer` on `spans` (outside which it must be zero), laid out for `kernel`.
void copy_layer_rows(const LayerImage& layer, const std::vector<RowSpan>& spans, const EllipticalKernel& kernel,
                     LayerRows& rows);
// The layer as a rectangle (zeros outside its spans), for the FFT.
LayerImage layer_image_of(const LayerRows& rows);

// Receives output row `row` of the blurred rectangle (the layer's rectangle grown by the kernel's
// radii: row 0 is y0 - radius_y), its pixels [first, first + count) of that rectangle as RGBA.
// Called from the worker threads, each row once; it must touch only that row's data.
using BlurredRowSink = std::function<void(int row, int first, int count, const float* rgba)>;

// A kernel's nonzero taps as the direct sum reads them (row by row, and for the AVX-512 form by
// their offset modulo 4), made once for a layer that is summed in several calls (the stage's tiles).
struct DirectSumTap {
  int dx;
  float weight;
};
struct DirectSumTapClass {
  int first_offset_px = 0;     // p = -dx of the class's first tap
  std::vector<float> weights;  // taps p, p + 4, ... (0 where the row has none)
};
struct DirectSumKernel {
  int radius_x_px = 0, radius_y_px = 0;
  std::vector<std::vector<DirectSumTap>> taps;          // kernel row dy + radius_y, left to right
  std::vector<std::vector<DirectSumTapClass>> classes;  // the same rows' taps by class
};
DirectSumKernel direct_sum_kernel(const EllipticalKernel& kernel);

// The direct sum of the layer with `kernel`, each output row on blurred_row_spans(rows.spans),
// handed to `sink`. Rows are split over `threads`; each value is the same whatever the count.
// rows must have been laid out for this kernel.
void blur_rows_direct(const LayerRows& rows, const EllipticalKernel& kernel, int threads, VectorIsa isa,
                      const BlurredRowSink& sink);
// The same for the output rows [first_row, last_row) only (rows of the grown rectangle, row 0 at
// rows.y0_px - radius_y), with the kernel's taps made beforehand: each value has the bits of the
// call above, whatever rows `rows` holds beyond those the range reads.
void blur_rows_direct(const LayerRows& rows, const DirectSumKernel& kernel, int first_row, int last_row, int threads,
                      VectorIsa isa, const BlurredRowSink& sink);
// The FFT's padded grids and spectra, one a channel, and the kernel's: kept by a caller that blurs
// layer after layer, frame after frame, made again only for another padded size and zeroed again
// before each use (so the result does not depend on what they held).
struct LayerFftBuffers {
  int rows = 0, cols = 0;
  std::vector<FftwFloatBuffer<float>> grids;
  std::vector<FftwFloatBuffer<std::complex<float>>> spectra;
  FftwFloatBuffer<float> kernel_real;
  FftwFloatBuffer<std::complex<float>> kernel_spectrum;
};

// The same convolution by FFT (stimuli/depth_of_field_blur.cpp), its rows handed to `sink` on the
// same spans; the channels are split over `threads`, each computed the same way whatever the count.
void blur_rows_fft(const LayerRows& rows, const EllipticalKernel& kernel, int threads, const BlurredRowSink& sink,
                   LayerFftBuffers& buffers);

}  // namespace glarelab

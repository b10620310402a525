#pragma once
// The display-kernel convolution (glare/analytic/display_kernel_convolution.h) in two levels, for a whole-display
// kernel whose sharp part is small: K = K_near + K_far with
//   K_near = w K, w(r) = 1 inside near_inner_px, a raised-cosine cross-fade to 0 at near_outer_px
//            (r the offset's length in pixels), convolved exactly at full resolution: one FFT of
//            the frame padded by near_outer_px (the small support makes the padded transform a
//            quarter of the full path's, which pads by the whole frame);
//   K_far  = (1 - w) K, smooth (the cross-fade leaves no edge), convolved at 1/factor of the
//            resolution: the frame area-averaged over factor x factor blocks, convolved with the
//            coarse kernel Kc(D) = sum_d t(d) K_far(factor D + d), t(d) = (f - |dx|)(f - |dy|) / f^2
//            (K_far integrated over a coarse pixel against the box of the source block: the
//            block-to-block energy), then bilinearly interpolated back to full resolution.
// Energy is kept exactly (up to float rounding), on the whole plane the output covers: the split
// is exact (K_near + K_far = K); the box average keeps the frame's sum (times factor^2); t's
// weights of one fine offset over all coarse offsets sum to 1, so sum Kc = sum K_far; bilinear
// interpolation at the fine pixel centres gives each coarse sample weights that sum to factor^2
// (the hat function's samples at spacing 1 / factor sum to factor per axis). A frame's own output
// loses what falls beyond its edges, as the full path's does.
//
// The coarse output is computed one coarse pixel beyond the frame on every side so the
// interpolation at the frame's edge has its neighbours; offsets beyond the kernel's half size
// count as 0 (the full path's kernel reaches every pixel of the frame from every other).
//
// Components and weights as in DisplayKernelConvolution: a Spencer mixture keeps the near and the
// coarse far spectra of each component and recombines both when the adaptation changes.
#include <memory>
#include <vector>

#include "core/image.h"
#include "glare/analytic/display_glare_kernel.h"
#include "glare/analytic/display_kernel_convolution.h"

namespace glarelab {

struct TwoLevelSplit {
  int near_inner_px = 64;  // K_near = K inside this radius
  int near_outer_px = 128; // ... and 0 from this radius on (the cross-fade between)
  int factor = 4;          // the far part's decimation: 2 or 4
};

// Refuses (std::invalid_argument, "glare/analytic/analytic_two_level: ...") a split that is not
// 0 <= inner < outer, factor 2 or 4 (or 1: no decimation).
void check_two_level_split(const TwoLevelSplit& split);

// The cross-fade weight at a distance of r_px pixels.
double near_weight(const TwoLevelSplit& split, double r_px);

// K_near: w K over offsets up to min(near_outer_px, the kernel's half size).
DisplayKernel near_kernel(const DisplayKernel& kernel, const TwoLevelSplit& split);

// Kc for coarse offsets up to coarse_half_width x coarse_half_height, from K_far = (1 - w) K.
DisplayKernel coarse_far_kernel(const DisplayKernel& kernel, const TwoLevelSplit& split, int coarse_half_width_px,
                                int coarse_half_height_px);

class TwoLevelConvolution {
 public:
  // Frames of width x height, kernels of half size width - 1 x height - 1 (the whole display).
  TwoLevelConvolution(int width_px, int height_px, const TwoLevelSplit& split, int threads = kGlareCpuThreads);

  void set_components(const std::vector<DisplayKernel>& components);
  void set_weights(const std::vector<double>& weights);
  bool has_kernel() const { return near_.has_kernel(); }
  // False when the near part is the whole kernel (then there is no far level).
  bool has_far_level() const { return far_level_; }
  std::size_t spectrum_bytes() const;
  const TwoLevelSplit& split() const { return split_; }
  int near_fft_rows() const { return near_.fft_rows(); }
  int near_fft_cols() const { return near_.fft_cols(); }
  int far_fft_rows() const { return far_ ? far_->fft_rows() : 0; }
  int far_fft_cols() const { return far_ ? far_->fft_cols() : 0; }

  // out = source convolved with the kernel (alpha copied). Refuses what DisplayKernelConvolution
  // refuses.
  void convolve(const ImageRGBA& source, ImageRGBA& out);

 private:
  int width_, height_, threads_;
  TwoLevelSplit split_;
  int near_half_width_, near_half_height_;
  bool far_level_ = false;
  int coarse_width_ = 0, coarse_height_ = 0;  // blocks covering the frame
  DisplayKernelConvolution near_;
  std::unique_ptr<DisplayKernelConvolution> far_;  // on (coarse + 2) x (coarse + 2): one block margin
  ImageRGBA coarse_in_, coarse_out_;
};

}  // namespace glarelab

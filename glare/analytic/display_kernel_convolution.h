#pragma once
// Convolution of frames of one size with display kernels of one size (glare/analytic/display_glare_kernel.h:
// offsets up to half_width x half_height pixels, so a kernel twice the frame reaches from every
// pixel to every other), by FFT, zero padded so the circular convolution equals the linear one
// for every output pixel: rows >= H + half_height, cols >= W + half_width (an offset o wraps onto
// another offset o' only if |o - o'| = the size, which needs |o| up to W - 1 of the frame plus
// |o'| up to half_width of the kernel).
//
// Float32 and planned (glare/cpu/fftw_float_plan.h: row passes skip the zero rows below the frame, the
// inverse computes only the frame's rows); the kernel's spectrum is computed once per kernel
// (from the kernel in double, rounded to float), or combined from the spectra of components
// (a Spencer mixture: f0, f1, f2 achromatic, the halo f3 per channel) when only their weights
// change. convolve_with_kernel_float64 is the reference it is checked against.
#include <array>
#include <complex>
#include <vector>

#include "core/image.h"
#include "glare/analytic/display_glare_kernel.h"
#include "glare/cpu/fftw_float_plan.h"

namespace glarelab {

class DisplayKernelConvolution {
 public:
  DisplayKernelConvolution(int width_px, int height_px, int kernel_half_width_px, int kernel_half_height_px,
                           int threads = kGlareCpuThreads);
  int fft_rows() const { return rows_; }
  int fft_cols() const { return cols_; }

  // Components whose weighted sum is the kernel (each 1 or 3 channels, all of the planned size);
  // their spectra are kept. Then set_weights picks the sum.
  void set_components(const std::vector<DisplayKernel>& components);
  // The kernel sum_i weights[i] components[i] (per channel; a 1-channel component serves all three).
  void set_weights(const std::vector<double>& weights);
  const std::vector<double>& weights() const { return weights_; }
  bool has_kernel() const { return has_kernel_; }
  std::size_t spectrum_bytes() const;

  // out = source convolved with the kernel, R, G, B (alpha copied from source). Refuses
  // (std::invalid_argument) a wrong size and NaN, Inf or negative values.
  void convolve(const ImageRGBA& source, ImageRGBA& out);

 private:
  std::size_t real_size() const { return static_cast<std::size_t>(rows_) * cols_; }
  std::size_t spectrum_size() const { return static_cast<std::size_t>(rows_) * (cols_ / 2 + 1); }

  int width_ = 0, height_ = 0, half_width_ = 0, half_height_ = 0, rows_ = 0, cols_ = 0, threads_ = 1;
  // Per component and channel (1 or 3): its spectrum.
  struct ComponentSpectrum {
    int channels = 1;
    std::vector<FftwFloatBuffer<std::complex<float>>> spectra;
  };
  std::vector<ComponentSpectrum> components_;
  std::vector<double> weights_;
  bool has_kernel_ = false;
  FftwFloatBuffer<std::complex<float>> kernel_spectrum_;  // 3 channels, the weighted sum
  FftwFloatBuffer<float> kernel_real_, image_real_, result_real_;
  FftwFloatBuffer<std::complex<float>> image_spectrum_;
  FftwFloatPlan image_row_pass_, image_column_pass_, inverse_column_pass_, inverse_row_pass_;
};

// The reference: the same linear convolution in float64 with FFTW, no planning tricks.
ImageRGBA convolve_with_kernel_float64(const ImageRGBA& source, const DisplayKernel& kernel);

}  // namespace glarelab

#pragma once
// The RGB convolution of convolution_cpu.h (zero padded to a 2,3,5,7-smooth size >= image + PSF - 1,
// so the circular convolution is the linear one) in float32 for a stream of frames of one size:
// FFTW plans and buffers made once, the three channels transformed by one plan each way, on
// kGlareCpuThreads threads. The scene's spectrum is kept: a static scene (the same image frame
// after frame, a new PSF each frame) costs 3 forward + 3 inverse transforms, a new scene 3 more.
// Each 2D transform is a row pass and a column pass of 1D FFTW transforms, so that the row pass
// skips the rows that are zero padding (forward: all rows below the image, below the PSF, which is
// only M of its rows x cols) or not wanted (inverse: all rows outside the image's); the column pass
// runs in place (faster than FFTW's out-of-place column transforms that preserve their input).
// Checked against convolve_image_cpu in float64 (tests/glare_cpu_float_test.cpp).
#include <complex>

#include "core/image.h"
#include "glare/fftw_float_plan.h"
#include "glare/psf.h"

namespace glarelab {

class CpuFloatConvolution {
 public:
  // Frames of width x height pixels with PSFs of kernel_px x kernel_px (display scale).
  CpuFloatConvolution(int width_px, int height_px, int kernel_px, int threads = kGlareCpuThreads);
  int fft_rows() const { return rows_; }
  int fft_cols() const { return cols_; }

  // A new scene: its R, G, B forward transforms, kept for every convolve() until the next one.
  // Refuses (std::invalid_argument) a wrong size and NaN, Inf or negative R, G, B, as convolve_image_cpu.
  void set_scene(const ImageRGBA& image);
  // The scene convolved with `psf` (1 or 3 channels, kernel_px wide) into `out` (resized once);
  // alpha and depth copied from the scene.
  void convolve(const Psf& psf, ImageRGBA& out);

 private:
  int width_ = 0, height_ = 0, kernel_px_ = 0, rows_ = 0, cols_ = 0, threads_ = 1;
  bool has_scene_ = false;
  ImageRGBA scene_;
  FftwFloatBuffer<float> image_real_, kernel_real_, result_real_;
  FftwFloatBuffer<std::complex<float>> image_spectrum_, kernel_spectrum_;
  // Clears rows [first_row, rows) of the three spectra in `spectrum` (the row pass leaves there
  // what the in-place column pass of the last frame wrote).
  void clear_rows(std::complex<float>* spectrum, int first_row) const;
  FftwFloatPlan image_row_pass_, image_column_pass_, kernel_row_pass_, kernel_column_pass_;
  FftwFloatPlan inverse_column_pass_, inverse_row_pass_;
};

}  // namespace glarelab

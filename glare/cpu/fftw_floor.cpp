#include "glare/cpu/fftw_floor.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace glarelab {

FftwFloatFloor::FftwFloatFloor(int psf_grid_px, int rows, int cols, int threads) {
  if (psf_grid_px < 2 || rows < 2 || cols < 2) throw std::invalid_argument("glare/cpu/fftw_floor: sizes must be >= 2");
  const std::size_t n2 = static_cast<std::size_t>(psf_grid_px) * psf_grid_px;
  const std::size_t real_size = static_cast<std::size_t>(rows) * cols;
  const std::size_t spectrum_size = static_cast<std::size_t>(rows) * (cols / 2 + 1);
  field_ = FftwFloatBuffer<std::complex<float>>(n2);
  field_spectrum_ = FftwFloatBuffer<std::complex<float>>(n2);
  real_in_ = FftwFloatBuffer<float>(6 * real_size);
  real_out_ = FftwFloatBuffer<float>(3 * real_size);
  image_spectrum_ = FftwFloatBuffer<std::complex<float>>(3 * spectrum_size);
  psf_spectrum_ = FftwFloatBuffer<std::complex<float>>(3 * spectrum_size);
  // Measured plans: the fastest FFTW does these transforms (glare/cpu/fftw_float_plan.h). They overwrite
  // their arrays, so the data is written after them.
  constexpr FftwPlanning measured = FftwPlanning::measure;
  psf_fft_ = FftwFloatPlan::complex_forward(psf_grid_px, psf_grid_px, field_.data(), field_spectrum_.data(), threads, measured);
  for (int k = 0; k < 6; ++k) {
    std::complex<float>* out = (k < 3 ? image_spectrum_.data() : psf_spectrum_.data()) + (k % 3) * spectrum_size;
    forward_[k] = FftwFloatPlan::real_forward(rows, cols, 1, real_in_.data() + k * real_size, out, threads, measured);
  }
  for (int k = 0; k < 3; ++k)
    inverse_[k] = FftwFloatPlan::real_inverse(rows, cols, 1, psf_spectrum_.data() + k * spectrum_size,
                                              real_out_.data() + k * real_size, threads, measured);
  // The glare path's estimate plans made after this are the ones they would be without the floor.
  forget_fftw_float_wisdom();
  // Data like a frame's: a disc of ones in the field, a small block in every real input.
  for (std::size_t k = 0; k < n2; k += 7) field_[k] = {1.0f, 0.0f};
  for (std::size_t k = 0; k < 6 * real_size; k += 5) real_in_[k] = 1.0f;
}

void FftwFloatFloor::run() {
  psf_fft_.execute();
  for (const FftwFloatPlan& plan : forward_) plan.execute();
  // The inverse destroys its input, the PSF spectrum, which the forward transforms above rewrite.
  for (const FftwFloatPlan& plan : inverse_) plan.execute();
}

FftwRgbConvolutionFloor::FftwRgbConvolutionFloor(int rows, int cols, int threads)
    : real_size_(static_cast<std::size_t>(rows) * cols),
      real_(3 * real_size_),
      spectrum_(3 * static_cast<std::size_t>(rows) * (cols / 2 + 1)),
      forward_(FftwFloatPlan::real_forward(rows, cols, 3, real_.data(), spectrum_.data(), threads)),
      inverse_(FftwFloatPlan::real_inverse(rows, cols, 3, spectrum_.data(), real_.data(), threads)) {}

FftwComplexFloor::FftwComplexFloor(int grid_px, int threads) : threads_(std::max(1, threads)) {
  if (grid_px < 2) throw std::invalid_argument("glare/cpu/fftw_floor: sizes must be >= 2");
  const std::size_t n2 = static_cast<std::size_t>(grid_px) * grid_px;
  field_ = FftwFloatBuffer<std::complex<double>>(n2);
  spectrum_ = FftwFloatBuffer<std::complex<double>>(n2);
  fft_ = FftwDoublePlan::measured_complex_forward(grid_px, grid_px, field_.data(), spectrum_.data());
  for (std::size_t k = 0; k < n2; k += 7) field_[k] = {1.0, 0.0};
}

double FftwComplexFloor::run_s() {
  const auto start = std::chrono::steady_clock::now();
  fft_.execute();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / threads_;
}

double FftwRgbConvolutionFloor::run_s() {
  for (std::size_t i = 0; i < 3 * real_size_; i += 97) real_[i] = 1.0f;
  const auto start = std::chrono::steady_clock::now();
  forward_.execute();
  inverse_.execute();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace glarelab

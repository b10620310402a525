#include "glare/cpu_float_convolution.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "glare/fft_cpu.h"
#include "glare/parallel_rows.h"

namespace glarelab {

CpuFloatConvolution::CpuFloatConvolution(int width_px, int height_px, int kernel_px, int threads)
    : width_(width_px), height_(height_px), kernel_px_(kernel_px), threads_(std::max(1, threads)) {
  if (width_px <= 0 || height_px <= 0 || kernel_px <= 0)
    throw std::invalid_argument("glare/cpu_float_convolution: image and PSF sizes must be > 0");
  rows_ = good_fft_size(height_px + kernel_px - 1);
  cols_ = good_fft_size(width_px + kernel_px - 1);
  const std::size_t real_size = static_cast<std::size_t>(rows_) * cols_;
  const std::size_t spectrum_size = static_cast<std::size_t>(rows_) * (cols_ / 2 + 1);
  // Zero padding: written once here; each frame writes only the image and kernel regions.
  image_real_ = FftwFloatBuffer<float>(3 * real_size);
  kernel_real_ = FftwFloatBuffer<float>(3 * real_size);
  result_real_ = FftwFloatBuffer<float>(3 * real_size);
  image_spectrum_ = FftwFloatBuffer<std::complex<float>>(3 * spectrum_size);
  kernel_spectrum_ = FftwFloatBuffer<std::complex<float>>(3 * spectrum_size);
  image_row_pass_ =
      FftwFloatPlan::real_rows_forward(rows_, cols_, 3, 0, height_px, image_real_.data(), image_spectrum_.data(), threads_);
  image_column_pass_ = FftwFloatPlan::complex_columns(rows_, cols_, 3, -1, image_spectrum_.data(), image_spectrum_.data(),
                                                      false, threads_);
  kernel_row_pass_ =
      FftwFloatPlan::real_rows_forward(rows_, cols_, 3, 0, kernel_px, kernel_real_.data(), kernel_spectrum_.data(), threads_);
  kernel_column_pass_ = FftwFloatPlan::complex_columns(rows_, cols_, 3, -1, kernel_spectrum_.data(),
                                                       kernel_spectrum_.data(), false, threads_);
  inverse_column_pass_ = FftwFloatPlan::complex_columns(rows_, cols_, 3, +1, kernel_spectrum_.data(),
                                                        kernel_spectrum_.data(), false, threads_);
  inverse_row_pass_ = FftwFloatPlan::real_rows_inverse(rows_, cols_, 3, kernel_px / 2, height_px, kernel_spectrum_.data(),
                                                       result_real_.data(), threads_);
}

void CpuFloatConvolution::clear_rows(std::complex<float>* spectrum, int first_row) const {
  const std::size_t spectrum_cols = static_cast<std::size_t>(cols_ / 2 + 1);
  const std::size_t spectrum_size = static_cast<std::size_t>(rows_) * spectrum_cols;
  for (int c = 0; c < 3; ++c)
    std::fill(spectrum + c * spectrum_size + first_row * spectrum_cols, spectrum + (c + 1) * spectrum_size,
              std::complex<float>{});
}

void CpuFloatConvolution::set_scene(const ImageRGBA& image) {
  if (image.width_px != width_ || image.height_px != height_)
    throw std::invalid_argument("glare/cpu_float_convolution: the image is " + std::to_string(image.width_px) + " x " +
                                std::to_string(image.height_px) + ", planned for " + std::to_string(width_) + " x " +
                                std::to_string(height_));
  const NonFiniteReport pixels = inspect_pixels(image);
  if (!pixels.clean())
    throw std::invalid_argument("glare/cpu_float_convolution: the image cannot be convolved: it has " + pixels.describe());
  scene_ = image;
  const std::size_t real_size = static_cast<std::size_t>(rows_) * cols_;
  parallel_chunks(height_, threads_, [&](int first, int last) {
    for (int y = first; y < last; ++y)
      for (int x = 0; x < width_; ++x) {
        const float* p = &image.rgba[4 * (static_cast<std::size_t>(y) * width_ + x)];
        for (int c = 0; c < 3; ++c) image_real_[c * real_size + static_cast<std::size_t>(y) * cols_ + x] = p[c];
      }
  });
  image_row_pass_.execute();
  clear_rows(image_spectrum_.data(), height_);
  image_column_pass_.execute();
  has_scene_ = true;
}

void CpuFloatConvolution::convolve(const Psf& psf, ImageRGBA& out) {
  if (!has_scene_) throw std::logic_error("glare/cpu_float_convolution: convolve before set_scene");
  if (psf.size_px != kernel_px_ || (psf.channels != 1 && psf.channels != 3))
    throw std::invalid_argument("glare/cpu_float_convolution: the PSF is not the planned size, or not 1 or 3 channels");
  const std::size_t real_size = static_cast<std::size_t>(rows_) * cols_;
  const int m = kernel_px_;
  for (int c = 0; c < 3; ++c) {
    const int channel = psf.channels == 3 ? c : 0;
    for (int y = 0; y < m; ++y)
      for (int x = 0; x < m; ++x)
        kernel_real_[c * real_size + static_cast<std::size_t>(y) * cols_ + x] = static_cast<float>(psf.at(channel, x, y));
  }
  kernel_row_pass_.execute();
  clear_rows(kernel_spectrum_.data(), kernel_px_);
  kernel_column_pass_.execute();
  // The product of the spectra, with the 1 / (rows cols) of the unnormalised inverse folded in.
  const float inverse_size = static_cast<float>(1.0 / (static_cast<double>(rows_) * cols_));
  const int spectrum_rows = 3 * rows_;
  const std::size_t spectrum_cols = static_cast<std::size_t>(cols_ / 2 + 1);
  // Written out: std::complex's operator* checks for NaN (C99 Annex G), which costs here and cannot
  // trigger (set_scene refuses non-finite images, the PSF is finite).
  float* kernel = reinterpret_cast<float*>(kernel_spectrum_.data());
  const float* image = reinterpret_cast<const float*>(image_spectrum_.data());
  parallel_chunks(spectrum_rows, threads_, [&](int first, int last) {
    for (std::size_t k = 2 * first * spectrum_cols; k < 2 * last * spectrum_cols; k += 2) {
      const float a = kernel[k], b = kernel[k + 1], c = image[k] * inverse_size, d = image[k + 1] * inverse_size;
      kernel[k] = a * c - b * d;
      kernel[k + 1] = a * d + b * c;
    }
  });
  inverse_column_pass_.execute();
  inverse_row_pass_.execute();
  // full(y, x) = sum img(y', x') psf(y - y', x - x'); the PSF's centre is (M/2, M/2).
  if (out.width_px != width_ || out.height_px != height_ || out.rgba.size() != scene_.rgba.size()) out = scene_;
  parallel_chunks(height_, threads_, [&](int first, int last) {
    for (int y = first; y < last; ++y)
      for (int x = 0; x < width_; ++x) {
        const std::size_t pixel = static_cast<std::size_t>(y) * width_ + x;
        float* target = &out.rgba[4 * pixel];
        for (int c = 0; c < 3; ++c)
          target[c] = result_real_[c * real_size + static_cast<std::size_t>(y + m / 2) * cols_ + (x + m / 2)];
        target[3] = scene_.rgba[4 * pixel + 3];
      }
  });
}

}  // namespace glarelab

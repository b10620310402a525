#include "glare/cpu_float_convolution.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "glare/fft_cpu.h"
#include "glare/parallel_rows.h"

namespace glarelab {

CpuFloatConvolution::CpuFloatConvolution(int width_px, int height_px, int kernel_px, int threads,
                                         ConvolutionOutput output, int slots)
    : width_(width_px),
      height_(height_px),
      kernel_px_(kernel_px),
      threads_(std::max(1, threads)),
      slots_(slots),
      output_(output) {
  if (width_px <= 0 || height_px <= 0 || kernel_px <= 0)
    throw std::invalid_argument("glare/cpu_float_convolution: image and PSF sizes must be > 0");
  if (slots < 1) throw std::invalid_argument("glare/cpu_float_convolution: at least one scene slot");
  // Padding. `full` keeps the whole linear convolution, image + M - 1 values each way. `same` keeps
  // only the image's values, full indices [M/2, M/2 + size): the circular convolution of length L
  // folds full index j >= L onto j - L, and the last one, size + M - 2, folds below M/2 when
  // L >= size + M/2, which also holds the last value read (M/2 + size - 1). The PSF needs L >= M.
  const auto padded = [&](int size) {
    const int needed = output == ConvolutionOutput::full ? size + kernel_px - 1 : std::max(size + kernel_px / 2, kernel_px);
    return smooth_fft_size(needed);
  };
  rows_ = padded(height_px);
  cols_ = padded(width_px);
  const std::size_t real_size = static_cast<std::size_t>(rows_) * cols_;
  const std::size_t spectrum_size = static_cast<std::size_t>(rows_) * (cols_ / 2 + 1);
  // Zero padding: written once, after the plans (which may write over their arrays while they are
  // measured); each frame writes only the image and kernel regions.
  image_real_ = FftwFloatBuffer<float>(3 * real_size);
  kernel_real_ = FftwFloatBuffer<float>(3 * real_size);
  result_real_ = FftwFloatBuffer<float>(3 * real_size);
  image_spectrum_ = FftwFloatBuffer<std::complex<float>>(3 * spectrum_size);
  kernel_spectrum_ = FftwFloatBuffer<std::complex<float>>(3 * spectrum_size);
  // `same` (one PSF per scene): the product overwrites the PSF's spectrum in place, as the inverse
  // destroys its input anyway; `full` keeps the PSF's spectrum for the next slot.
  if (output == ConvolutionOutput::full) product_ = FftwFloatBuffer<std::complex<float>>(3 * spectrum_size);
  std::complex<float>* product = output == ConvolutionOutput::full ? product_.data() : kernel_spectrum_.data();
  if (slots > 1)
    for (int k = 0; k < slots; ++k) scene_spectra_.emplace_back(3 * spectrum_size);
  has_scene_.assign(static_cast<std::size_t>(slots), false);
  // Measured plans kept in the wisdom file (fftw_float_plan.h): the column passes' strided
  // transforms are where FFTW_ESTIMATE's plans lose most (1.6 to 2.2 times FFTW_MEASURE's here).
  constexpr FftwPlanning kept = FftwPlanning::kept;
  image_row_pass_ = FftwFloatPlan::real_rows_forward(rows_, cols_, 3, 0, height_px, image_real_.data(),
                                                     image_spectrum_.data(), threads_, kept);
  image_column_pass_ = FftwFloatPlan::complex_columns(rows_, cols_, 3, -1, image_spectrum_.data(), image_spectrum_.data(),
                                                      false, threads_, kept);
  kernel_row_pass_ = FftwFloatPlan::real_rows_forward(rows_, cols_, 3, 0, kernel_px, kernel_real_.data(),
                                                      kernel_spectrum_.data(), threads_, kept);
  kernel_column_pass_ = FftwFloatPlan::complex_columns(rows_, cols_, 3, -1, kernel_spectrum_.data(),
                                                       kernel_spectrum_.data(), false, threads_, kept);
  inverse_column_pass_ = FftwFloatPlan::complex_columns(rows_, cols_, 3, +1, product, product, false, threads_, kept);
  // The rows of the result that are kept: the image's, shifted by the PSF's centre (`same`), or all
  // of the linear convolution's height + M - 1 (`full`).
  const int first_row = output == ConvolutionOutput::same ? kernel_px / 2 : 0;
  const int row_count = output == ConvolutionOutput::same ? height_px : height_px + kernel_px - 1;
  inverse_row_pass_ = FftwFloatPlan::real_rows_inverse(rows_, cols_, 3, first_row, row_count, product,
                                                       result_real_.data(), threads_, kept);
  std::fill(image_real_.data(), image_real_.data() + image_real_.size(), 0.0f);
  std::fill(kernel_real_.data(), kernel_real_.data() + kernel_real_.size(), 0.0f);
}

void CpuFloatConvolution::clear_rows(std::complex<float>* spectrum, int first_row) const {
  const std::size_t spectrum_cols = static_cast<std::size_t>(cols_ / 2 + 1);
  const std::size_t spectrum_size = static_cast<std::size_t>(rows_) * spectrum_cols;
  for (int c = 0; c < 3; ++c)
    std::fill(spectrum + c * spectrum_size + first_row * spectrum_cols, spectrum + (c + 1) * spectrum_size,
              std::complex<float>{});
}

void CpuFloatConvolution::transform_scene(const ImageRGBA& image, int x0, int y0, int slot) {
  if (slot < 0 || slot >= slots_) throw std::invalid_argument("glare/cpu_float_convolution: no scene slot " + std::to_string(slot));
  const std::size_t real_size = static_cast<std::size_t>(rows_) * cols_;
  // `same` output keeps the scene's alpha for convolve() (not the whole scene: a copy of it was a
  // frame-sized pass of its own), read into incoming_alpha_ and swapped in once the scene is
  // accepted, so that a refused scene leaves the last one's.
  const bool keep_alpha = output_ == ConvolutionOutput::same;
  if (keep_alpha) incoming_alpha_.resize(static_cast<std::size_t>(width_) * height_);
  std::atomic<bool> clean = true;
  parallel_chunks(height_, threads_, [&](int first, int last) {
    bool chunk_clean = true;
    for (int y = first; y < last; ++y) {
      const float* source = image.pixel(x0, y0 + y);
      for (int x = 0; x < width_; ++x) {
        const float* p = source + 4 * x;
        for (int c = 0; c < 3; ++c) {
          // NaN fails both comparisons: refused, as convolve_image_cpu refuses it.
          chunk_clean = chunk_clean && p[c] >= 0.0f && p[c] <= std::numeric_limits<float>::max();
          image_real_[c * real_size + static_cast<std::size_t>(y) * cols_ + x] = p[c];
        }
        if (keep_alpha) incoming_alpha_[static_cast<std::size_t>(y) * width_ + x] = p[3];
      }
    }
    if (!chunk_clean) clean = false;
  });
  if (!clean) {
    ImageRGBA region(width_, height_);
    for (int y = 0; y < height_; ++y) std::copy_n(image.pixel(x0, y0 + y), 4 * width_, region.pixel(0, y));
    throw std::invalid_argument("glare/cpu_float_convolution: the image cannot be convolved: it has " +
                                inspect_pixels(region).describe());
  }
  if (keep_alpha) scene_alpha_.swap(incoming_alpha_);
  image_row_pass_.execute();
  clear_rows(image_spectrum_.data(), height_);
  image_column_pass_.execute();
  if (!scene_spectra_.empty())
    std::memcpy(scene_spectra_[static_cast<std::size_t>(slot)].data(), image_spectrum_.data(),
                image_spectrum_.size() * sizeof(std::complex<float>));
  has_scene_[static_cast<std::size_t>(slot)] = true;
}

void CpuFloatConvolution::set_scene(const ImageRGBA& image, int slot) {
  if (image.width_px != width_ || image.height_px != height_)
    throw std::invalid_argument("glare/cpu_float_convolution: the image is " + std::to_string(image.width_px) + " x " +
                                std::to_string(image.height_px) + ", planned for " + std::to_string(width_) + " x " +
                                std::to_string(height_));
  // transform_scene refuses non-finite and negative pixels as it copies them (no scan before it).
  transform_scene(image, 0, 0, slot);
  if (output_ == ConvolutionOutput::same) scene_depth_ = image.depth;
}

void CpuFloatConvolution::set_scene(const ImageRGBA& frame, int x0, int y0, int slot) {
  if (x0 < 0 || y0 < 0 || x0 + width_ > frame.width_px || y0 + height_ > frame.height_px)
    throw std::invalid_argument("glare/cpu_float_convolution: the region does not lie inside the frame");
  transform_scene(frame, x0, y0, slot);
}

void CpuFloatConvolution::set_kernel(const Psf& psf) {
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
  has_kernel_ = true;
}

void CpuFloatConvolution::multiply_and_invert(int slot) {
  // The product of the spectra, with the 1 / (rows cols) of the unnormalised inverse folded in.
  const float inverse_size = static_cast<float>(1.0 / (static_cast<double>(rows_) * cols_));
  const int spectrum_rows = 3 * rows_;
  const std::size_t spectrum_cols = static_cast<std::size_t>(cols_ / 2 + 1);
  // Written out: std::complex's operator* checks for NaN (C99 Annex G), which costs here and cannot
  // trigger (scenes with non-finite pixels are refused, the PSF is finite).
  const float* kernel = reinterpret_cast<const float*>(kernel_spectrum_.data());
  const float* image = reinterpret_cast<const float*>(spectrum(slot));
  float* product = reinterpret_cast<float*>(output_ == ConvolutionOutput::full ? product_.data() : kernel_spectrum_.data());
  parallel_chunks(spectrum_rows, threads_, [&](int first, int last) {
    for (std::size_t k = 2 * first * spectrum_cols; k < 2 * last * spectrum_cols; k += 2) {
      const float a = kernel[k], b = kernel[k + 1], c = image[k] * inverse_size, d = image[k + 1] * inverse_size;
      product[k] = a * c - b * d;
      product[k + 1] = a * d + b * c;
    }
  });
  inverse_column_pass_.execute();
  inverse_row_pass_.execute();
}

void CpuFloatConvolution::convolve(const Psf& psf, ImageRGBA& out) {
  if (output_ != ConvolutionOutput::same) throw std::logic_error("glare/cpu_float_convolution: convolve needs `same` output");
  if (!has_scene_[0]) throw std::logic_error("glare/cpu_float_convolution: convolve before set_scene");
  set_kernel(psf);
  multiply_and_invert(0);
  const std::size_t real_size = static_cast<std::size_t>(rows_) * cols_;
  const int m = kernel_px_;
  // full(y, x) = sum img(y', x') psf(y - y', x - x'); the PSF's centre is (M/2, M/2).
  if (out.width_px != width_ || out.height_px != height_ || out.rgba.size() != 4 * scene_alpha_.size())
    out = ImageRGBA(width_, height_);
  out.depth = scene_depth_;
  parallel_chunks(height_, threads_, [&](int first, int last) {
    for (int y = first; y < last; ++y)
      for (int x = 0; x < width_; ++x) {
        const std::size_t pixel = static_cast<std::size_t>(y) * width_ + x;
        float* target = &out.rgba[4 * pixel];
        for (int c = 0; c < 3; ++c)
          target[c] = result_real_[c * real_size + static_cast<std::size_t>(y + m / 2) * cols_ + (x + m / 2)];
        target[3] = scene_alpha_[pixel];
      }
  });
}

void CpuFloatConvolution::write_full(int slot, ImageRGBA& frame, int x0, int y0) {
  if (output_ != ConvolutionOutput::full) throw std::logic_error("glare/cpu_float_convolution: write_full needs `full` output");
  if (slot < 0 || slot >= slots_ || !has_scene_[static_cast<std::size_t>(slot)] || !has_kernel_)
    throw std::logic_error("glare/cpu_float_convolution: write_full before set_scene and set_kernel");
  multiply_and_invert(slot);
  const std::size_t real_size = static_cast<std::size_t>(rows_) * cols_;
  const int m = kernel_px_;
  // Full index (fy, fx) is frame pixel (y0 - M/2 + fy, x0 - M/2 + fx), for fy < height + M - 1.
  const int fy0 = std::max(0, m / 2 - y0), fy1 = std::min(height_ + m - 1, frame.height_px - y0 + m / 2);
  const int fx0 = std::max(0, m / 2 - x0), fx1 = std::min(width_ + m - 1, frame.width_px - x0 + m / 2);
  if (fy1 <= fy0 || fx1 <= fx0) return;
  parallel_chunks(fy1 - fy0, threads_, [&](int first, int last) {
    for (int fy = fy0 + first; fy < fy0 + last; ++fy) {
      float* target = frame.pixel(x0 - m / 2 + fx0, y0 - m / 2 + fy);
      const std::size_t row = static_cast<std::size_t>(fy) * cols_;
      for (int fx = fx0; fx < fx1; ++fx, target += 4)
        for (int c = 0; c < 3; ++c) target[c] = result_real_[c * real_size + row + fx];
    }
  });
}

}  // namespace glarelab

#include "glare/analytic/display_kernel_convolution.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "core/fft_size.h"
#include "core/parallel_for.h"
#include "glare/cpu/fft.h"

namespace glarelab {

DisplayKernelConvolution::DisplayKernelConvolution(int width_px, int height_px, int kernel_half_width_px,
                                                   int kernel_half_height_px, int threads)
    : width_(width_px),
      height_(height_px),
      half_width_(kernel_half_width_px),
      half_height_(kernel_half_height_px),
      threads_(std::max(1, threads)) {
  if (width_px <= 0 || height_px <= 0 || kernel_half_width_px < 0 || kernel_half_height_px < 0)
    throw std::invalid_argument("glare/analytic/display_kernel_convolution: frame and kernel sizes must be positive");
  rows_ = good_fft_size(height_px + kernel_half_height_px);
  cols_ = good_fft_size(width_px + kernel_half_width_px);
  kernel_real_ = FftwFloatBuffer<float>(real_size());
  image_real_ = FftwFloatBuffer<float>(3 * real_size());
  result_real_ = FftwFloatBuffer<float>(3 * real_size());
  image_spectrum_ = FftwFloatBuffer<std::complex<float>>(3 * spectrum_size());
  kernel_spectrum_ = FftwFloatBuffer<std::complex<float>>(3 * spectrum_size());
  // The frame fills only its first height rows: the forward row pass skips the rest.
  image_row_pass_ =
      FftwFloatPlan::real_rows_forward(rows_, cols_, 3, 0, height_px, image_real_.data(), image_spectrum_.data(), threads_);
  image_column_pass_ = FftwFloatPlan::complex_columns(rows_, cols_, 3, -1, image_spectrum_.data(), image_spectrum_.data(),
                                                      false, threads_);
  inverse_column_pass_ = FftwFloatPlan::complex_columns(rows_, cols_, 3, +1, image_spectrum_.data(),
                                                        image_spectrum_.data(), false, threads_);
  inverse_row_pass_ = FftwFloatPlan::real_rows_inverse(rows_, cols_, 3, 0, height_px, image_spectrum_.data(),
                                                       result_real_.data(), threads_);
}

std::size_t DisplayKernelConvolution::spectrum_bytes() const {
  std::size_t count = 3;
  for (const ComponentSpectrum& c : components_) count += static_cast<std::size_t>(c.channels);
  return count * spectrum_size() * sizeof(std::complex<float>);
}

void DisplayKernelConvolution::set_components(const std::vector<DisplayKernel>& components) {
  components_.clear();
  has_kernel_ = false;
  weights_.clear();
  for (const DisplayKernel& kernel : components) {
    if (kernel.half_width_px != half_width_ || kernel.half_height_px != half_height_ ||
        (kernel.channels != 1 && kernel.channels != 3))
      throw std::invalid_argument("glare/analytic/display_kernel_convolution: a kernel is not of the planned size");
    ComponentSpectrum component;
    component.channels = kernel.channels;
    for (int c = 0; c < kernel.channels; ++c) {
      std::fill(kernel_real_.data(), kernel_real_.data() + real_size(), 0.0f);
      // Offset (dx, dy) goes to (dy mod rows, dx mod cols): the kernel's centre at the origin.
      for (int dy = -half_height_; dy <= half_height_; ++dy) {
        const std::size_t row = static_cast<std::size_t>((dy + rows_) % rows_) * cols_;
        for (int dx = -half_width_; dx <= half_width_; ++dx)
          kernel_real_[row + static_cast<std::size_t>((dx + cols_) % cols_)] = static_cast<float>(kernel.at(c, dx, dy));
      }
      FftwFloatBuffer<std::complex<float>> spectrum(spectrum_size());
      // Each spectrum its own plan (FFTW_ESTIMATE: cheap, and it leaves the input alone).
      FftwFloatPlan::real_forward(rows_, cols_, 1, kernel_real_.data(), spectrum.data(), threads_).execute();
      component.spectra.push_back(std::move(spectrum));
    }
    components_.push_back(std::move(component));
  }
}

void DisplayKernelConvolution::set_weights(const std::vector<double>& weights) {
  if (weights.size() != components_.size())
    throw std::invalid_argument("glare/analytic/display_kernel_convolution: one weight per component");
  weights_ = weights;
  const std::size_t n = spectrum_size();
  parallel_chunks(static_cast<int>(3 * rows_), threads_, [&](int first, int last) {
    const std::size_t per_row = static_cast<std::size_t>(cols_ / 2 + 1);
    for (int row = first; row < last; ++row) {
      const int c = row / rows_;
      const std::size_t begin = static_cast<std::size_t>(row % rows_) * per_row, end = begin + per_row;
      std::complex<float>* out = kernel_spectrum_.data() + c * n;
      for (std::size_t k = begin; k < end; ++k) {
        std::complex<double> sum{};
        for (std::size_t i = 0; i < components_.size(); ++i) {
          if (weights[i] == 0.0) continue;
          const ComponentSpectrum& comp = components_[i];
          const std::complex<float> v = comp.spectra[comp.channels == 3 ? c : 0][k];
          sum += weights[i] * std::complex<double>(v.real(), v.imag());
        }
        out[k] = std::complex<float>(static_cast<float>(sum.real()), static_cast<float>(sum.imag()));
      }
    }
  });
  has_kernel_ = true;
}

void DisplayKernelConvolution::convolve(const ImageRGBA& source, ImageRGBA& out) {
  if (!has_kernel_) throw std::logic_error("glare/analytic/display_kernel_convolution: convolve before set_weights");
  if (source.width_px != width_ || source.height_px != height_)
    throw std::invalid_argument("glare/analytic/display_kernel_convolution: the frame is " + std::to_string(source.width_px) +
                                " x " + std::to_string(source.height_px) + ", planned for " + std::to_string(width_) +
                                " x " + std::to_string(height_));
  const NonFiniteReport pixels = inspect_pixels(source);
  if (!pixels.clean())
    throw std::invalid_argument("glare/analytic/display_kernel_convolution: the frame cannot be convolved: it has " +
                                pixels.describe());
  const std::size_t real = real_size(), spectrum = spectrum_size();
  parallel_chunks(height_, threads_, [&](int first, int last) {
    for (int y = first; y < last; ++y)
      for (int x = 0; x < width_; ++x) {
        const float* p = &source.rgba[4 * (static_cast<std::size_t>(y) * width_ + x)];
        for (int c = 0; c < 3; ++c) image_real_[c * real + static_cast<std::size_t>(y) * cols_ + x] = p[c];
      }
  });
  image_row_pass_.execute();
  const std::size_t per_row = static_cast<std::size_t>(cols_ / 2 + 1);
  for (int c = 0; c < 3; ++c)
    std::fill(image_spectrum_.data() + c * spectrum + height_ * per_row, image_spectrum_.data() + (c + 1) * spectrum,
              std::complex<float>{});
  image_column_pass_.execute();
  // Product with the kernel's spectrum, the inverse's 1 / (rows cols) folded in; written out
  // (std::complex's operator* checks for NaN, which cannot occur here).
  const float inverse_size = static_cast<float>(1.0 / (static_cast<double>(rows_) * cols_));
  float* image = reinterpret_cast<float*>(image_spectrum_.data());
  const float* kernel = reinterpret_cast<const float*>(kernel_spectrum_.data());
  parallel_chunks(3 * rows_, threads_, [&](int first, int last) {
    for (std::size_t k = 2 * first * per_row; k < 2 * last * per_row; k += 2) {
      const float a = kernel[k] * inverse_size, b = kernel[k + 1] * inverse_size, c = image[k], d = image[k + 1];
      image[k] = a * c - b * d;
      image[k + 1] = a * d + b * c;
    }
  });
  inverse_column_pass_.execute();
  inverse_row_pass_.execute();
  if (out.width_px != width_ || out.height_px != height_ || out.rgba.size() != source.rgba.size()) out = source;
  parallel_chunks(height_, threads_, [&](int first, int last) {
    for (int y = first; y < last; ++y)
      for (int x = 0; x < width_; ++x) {
        const std::size_t pixel = static_cast<std::size_t>(y) * width_ + x;
        float* target = &out.rgba[4 * pixel];
        for (int c = 0; c < 3; ++c) target[c] = result_real_[c * real + static_cast<std::size_t>(y) * cols_ + x];
        target[3] = source.rgba[4 * pixel + 3];
      }
  });
}

ImageRGBA convolve_with_kernel_float64(const ImageRGBA& source, const DisplayKernel& kernel) {
  const int w = source.width_px, h = source.height_px;
  const int rows = good_fft_size(h + kernel.half_height_px), cols = good_fft_size(w + kernel.half_width_px);
  ImageRGBA out = source;
  for (int c = 0; c < 3; ++c) {
    const int kc = kernel.channels == 3 ? c : 0;
    std::vector<double> image(static_cast<std::size_t>(rows) * cols, 0.0), k(image.size(), 0.0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        image[static_cast<std::size_t>(y) * cols + x] = source.rgba[4 * (static_cast<std::size_t>(y) * w + x) + c];
    for (int dy = -kernel.half_height_px; dy <= kernel.half_height_px; ++dy)
      for (int dx = -kernel.half_width_px; dx <= kernel.half_width_px; ++dx)
        k[static_cast<std::size_t>((dy + rows) % rows) * cols + static_cast<std::size_t>((dx + cols) % cols)] =
            kernel.at(kc, dx, dy);
    std::vector<std::complex<double>> a = fft2d_real_forward(image, rows, cols), b = fft2d_real_forward(k, rows, cols);
    const double scale = 1.0 / (static_cast<double>(rows) * cols);
    for (std::size_t i = 0; i < a.size(); ++i) a[i] *= b[i] * scale;
    std::vector<double> result(static_cast<std::size_t>(rows) * cols);
    fft2d_real_inverse(a, result, rows, cols);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        out.rgba[4 * (static_cast<std::size_t>(y) * w + x) + c] = static_cast<float>(result[static_cast<std::size_t>(y) * cols + x]);
  }
  return out;
}

}  // namespace glarelab

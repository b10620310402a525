#include "glare/cpu/convolution.h"

#include <stdexcept>

#include "core/fft_size.h"
#include "glare/wave/psf_scale.h"

namespace glarelab {
namespace {

// Linear convolution through a padded circular one, in precision T.
template <typename T>
void fft_convolve(const std::vector<double>& plane, int width, int height, const Psf& psf, int channel, int rows,
                  int cols, std::vector<double>& out) {
  const int m = psf.size_px;
  std::vector<T> image_padded(static_cast<std::size_t>(rows) * cols, T(0));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      image_padded[static_cast<std::size_t>(y) * cols + x] = static_cast<T>(plane[static_cast<std::size_t>(y) * width + x]);
  std::vector<T> kernel_padded(static_cast<std::size_t>(rows) * cols, T(0));
  for (int y = 0; y < m; ++y)
    for (int x = 0; x < m; ++x) kernel_padded[static_cast<std::size_t>(y) * cols + x] = static_cast<T>(psf.at(channel, x, y));
  auto image_spectrum = fft2d_real_forward(image_padded, rows, cols);
  const auto kernel_spectrum = fft2d_real_forward(kernel_padded, rows, cols);
  for (std::size_t k = 0; k < image_spectrum.size(); ++k) image_spectrum[k] *= kernel_spectrum[k];
  std::vector<T> full;
  fft2d_real_inverse(image_spectrum, full, rows, cols);
  // full(y, x) = sum img(y', x') psf(y - y', x - x') * rows * cols; the PSF's centre is (M/2, M/2).
  const double inverse_size = 1.0 / (static_cast<double>(rows) * cols);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      out[static_cast<std::size_t>(y) * width + x] +=
          static_cast<double>(full[static_cast<std::size_t>(y + m / 2) * cols + (x + m / 2)]) * inverse_size;
}

}  // namespace

std::vector<double> convolve_plane_cpu(const std::vector<double>& plane, int width_px, int height_px, const Psf& psf,
                                       int psf_channel, const ConvolutionOptions& options, ConvolutionReport* report) {
  if (width_px <= 0 || height_px <= 0 || plane.size() != static_cast<std::size_t>(width_px) * height_px)
    throw std::invalid_argument("glare/cpu/convolution: plane size does not match width x height");
  if (psf.size_px <= 0 || psf_channel < 0 || psf_channel >= psf.channels)
    throw std::invalid_argument("glare/cpu/convolution: no such PSF channel");
  const int m = psf.size_px;
  const int rows = good_fft_size(height_px + m - 1);
  const int cols = good_fft_size(width_px + m - 1);
  std::vector<double> out(plane.size(), 0.0);
  std::vector<double> dim = plane;
  std::size_t bright = 0;
  if (options.bright_threshold > 0.0) {
    for (int y = 0; y < height_px; ++y)
      for (int x = 0; x < width_px; ++x) {
        const double value = plane[static_cast<std::size_t>(y) * width_px + x];
        if (value <= options.bright_threshold) continue;
        ++bright;
        dim[static_cast<std::size_t>(y) * width_px + x] = 0.0;
        // out(y + v - M/2, x + u - M/2) += value * psf(u, v), clipped to the image.
        for (int v = 0; v < m; ++v) {
          const int oy = y + v - m / 2;
          if (oy < 0 || oy >= height_px) continue;
          for (int u = 0; u < m; ++u) {
            const int ox = x + u - m / 2;
            if (ox < 0 || ox >= width_px) continue;
            out[static_cast<std::size_t>(oy) * width_px + ox] += value * psf.at(psf_channel, u, v);
          }
        }
      }
  }
  if (options.precision == FftPrecision::float64) {
    fft_convolve<double>(dim, width_px, height_px, psf, psf_channel, rows, cols, out);
  } else {
    fft_convolve<float>(dim, width_px, height_px, psf, psf_channel, rows, cols, out);
  }
  if (report != nullptr) {
    report->bright_pixels += bright;
    report->fft_rows = rows;
    report->fft_cols = cols;
  }
  return out;
}

ImageRGBA convolve_image_cpu(const ImageRGBA& image, const Psf& psf, const ConvolutionOptions& options,
                             ConvolutionReport* report) {
  if (psf.channels != 1 && psf.channels != 3)
    throw std::invalid_argument("glare/cpu/convolution: the PSF must have 1 or 3 channels");
  // One NaN or Inf would spread over the whole image through the FFT; negative luminance is not light.
  const NonFiniteReport pixels = inspect_pixels(image);
  if (!pixels.clean())
    throw std::invalid_argument("glare/cpu/convolution: the image cannot be convolved: it has " + pixels.describe());
  ImageRGBA out = image;
  const std::size_t count = static_cast<std::size_t>(image.width_px) * image.height_px;
  std::vector<double> plane(count);
  for (int c = 0; c < 3; ++c) {
    for (std::size_t k = 0; k < count; ++k) plane[k] = image.rgba[4 * k + static_cast<std::size_t>(c)];
    const auto result =
        convolve_plane_cpu(plane, image.width_px, image.height_px, psf, psf.channels == 3 ? c : 0, options, report);
    for (std::size_t k = 0; k < count; ++k) out.rgba[4 * k + static_cast<std::size_t>(c)] = static_cast<float>(result[k]);
  }
  return out;
}

ImageRGBA convolve_image_at_scale_cpu(const ImageRGBA& image, double image_degrees_per_pixel, const Psf& psf,
                                      const ConvolutionOptions& options, ConvolutionReport* report) {
  return convolve_image_cpu(image, resample_psf_to_display(psf, image_degrees_per_pixel), options, report);
}

}  // namespace glarelab

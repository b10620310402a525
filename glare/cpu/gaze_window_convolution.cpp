#include "glare/cpu/gaze_window_convolution.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

namespace glarelab {
namespace {

// One axis of the window: side `side` centred on `gaze_px`, shifted into [0, image).
int window_start(double gaze_px, int side, int image) {
  const int start = static_cast<int>(std::lround(gaze_px - 0.5 * side));
  return std::clamp(start, 0, std::max(0, image - side));
}

}  // namespace

GazeWindow place_gaze_window(int image_width_px, int image_height_px, double gaze_x, double gaze_y, int psf_size_px,
                             const GazeWindowOptions& options) {
  if (image_width_px <= 0 || image_height_px <= 0 || psf_size_px <= 0)
    throw std::invalid_argument("glare/gaze_window: empty image or PSF");
  if (options.window_px <= 0 || !std::has_single_bit(static_cast<unsigned>(options.window_px)))
    throw std::invalid_argument("glare/gaze_window: window side " + std::to_string(options.window_px) +
                                " px is not a power of two");
  if (!std::isfinite(gaze_x) || !std::isfinite(gaze_y))
    throw std::invalid_argument("glare/gaze_window: gaze is not finite");
  if (!(options.falloff_sigma_px >= 0.0) || !std::isfinite(options.falloff_sigma_px))
    throw std::invalid_argument("glare/gaze_window: falloff sigma must be >= 0 px");
  GazeWindow window;
  window.width_px = std::min(options.window_px, image_width_px);
  window.height_px = std::min(options.window_px, image_height_px);
  // A gaze off the display (tracker noise at the edge) is held at the display's edge.
  window.gaze_x_px = std::clamp(gaze_x, 0.0, 1.0) * image_width_px;
  window.gaze_y_px = std::clamp(gaze_y, 0.0, 1.0) * image_height_px;
  window.x0_px = window_start(window.gaze_x_px, window.width_px, image_width_px);
  window.y0_px = window_start(window.gaze_y_px, window.height_px, image_height_px);
  window.sigma_px = options.falloff_sigma_px > 0.0 ? options.falloff_sigma_px : options.window_px / 6.0;
  // The PSF's centre is (M/2, M/2): it reaches M/2 pixels one way and M - 1 - M/2 <= M/2 the other.
  const int reach = psf_size_px / 2;
  window.apron_px = options.apron_px < 0 ? reach : std::min(options.apron_px, reach);
  return window;
}

double gaze_blend_weight(const GazeWindow& window, int x, int y) {
  if (!window.contains(x, y)) return 0.0;
  const double dx = x + 0.5 - window.gaze_x_px;
  const double dy = y + 0.5 - window.gaze_y_px;
  return std::exp(-(dx * dx + dy * dy) / (2.0 * window.sigma_px * window.sigma_px));
}

std::vector<double> convolve_gaze_window_plane(const std::vector<double>& plane, int width_px, int height_px,
                                               const Psf& psf, int psf_channel, const GazeWindow& window,
                                               const ConvolutionOptions& options, ConvolutionReport* report) {
  if (width_px <= 0 || height_px <= 0 || plane.size() != static_cast<std::size_t>(width_px) * height_px)
    throw std::invalid_argument("glare/gaze_window: plane size does not match width x height");
  if (window.x0_px < 0 || window.y0_px < 0 || window.x0_px + window.width_px > width_px ||
      window.y0_px + window.height_px > height_px)
    throw std::invalid_argument("glare/gaze_window: the window does not lie inside the image");
  // The convolved area: the window plus the apron, clipped to the image. Beyond the image both this
  // and the full-frame convolution see zeros, so clipping costs no exactness.
  const int cx0 = std::max(0, window.x0_px - window.apron_px);
  const int cy0 = std::max(0, window.y0_px - window.apron_px);
  const int cx1 = std::min(width_px, window.x0_px + window.width_px + window.apron_px);
  const int cy1 = std::min(height_px, window.y0_px + window.height_px + window.apron_px);
  const int crop_width = cx1 - cx0;
  const int crop_height = cy1 - cy0;
  std::vector<double> crop(static_cast<std::size_t>(crop_width) * crop_height);
  for (int y = 0; y < crop_height; ++y)
    std::copy_n(plane.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(cy0 + y) * width_px + cx0),
                crop_width, crop.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * crop_width));
  const std::vector<double> convolved =
      convolve_plane_cpu(crop, crop_width, crop_height, psf, psf_channel, options, report);
  std::vector<double> out(static_cast<std::size_t>(window.width_px) * window.height_px);
  for (int y = 0; y < window.height_px; ++y)
    for (int x = 0; x < window.width_px; ++x)
      out[static_cast<std::size_t>(y) * window.width_px + x] =
          convolved[static_cast<std::size_t>(window.y0_px - cy0 + y) * crop_width + (window.x0_px - cx0 + x)];
  return out;
}

std::vector<double> blend_gaze_window_plane(const std::vector<double>& base, int width_px, int height_px,
                                            const std::vector<double>& windowed, const GazeWindow& window) {
  if (base.size() != static_cast<std::size_t>(width_px) * height_px ||
      windowed.size() != static_cast<std::size_t>(window.width_px) * window.height_px)
    throw std::invalid_argument("glare/gaze_window: plane sizes do not match the image and the window");
  std::vector<double> out = base;
  for (int y = 0; y < window.height_px; ++y)
    for (int x = 0; x < window.width_px; ++x) {
      const int ix = window.x0_px + x;
      const int iy = window.y0_px + y;
      const double w = gaze_blend_weight(window, ix, iy);
      double& pixel = out[static_cast<std::size_t>(iy) * width_px + ix];
      pixel += w * (windowed[static_cast<std::size_t>(y) * window.width_px + x] - pixel);
    }
  return out;
}

ImageRGBA blend_gaze_window(const ImageRGBA& base, const ImageRGBA& glared, const GazeWindow& window) {
  if (base.width_px != glared.width_px || base.height_px != glared.height_px)
    throw std::invalid_argument("glare/gaze_window: the glared frame and its base differ in size");
  ImageRGBA out = base;
  for (int y = window.y0_px; y < window.y0_px + window.height_px; ++y)
    for (int x = window.x0_px; x < window.x0_px + window.width_px; ++x) {
      const double w = gaze_blend_weight(window, x, y);
      for (int c = 0; c < 3; ++c) {
        const double from = base.pixel(x, y)[c];
        out.pixel(x, y)[c] = static_cast<float>(from + w * (static_cast<double>(glared.pixel(x, y)[c]) - from));
      }
    }
  return out;
}

ImageRGBA convolve_image_gaze_window_cpu(const ImageRGBA& image, const Psf& psf, double gaze_x, double gaze_y,
                                         const GazeWindowOptions& options, ConvolutionReport* report) {
  if (psf.channels != 1 && psf.channels != 3)
    throw std::invalid_argument("glare/gaze_window: the PSF must have 1 or 3 channels");
  const NonFiniteReport pixels = inspect_pixels(image);
  if (!pixels.clean())
    throw std::invalid_argument("glare/gaze_window: the image cannot be convolved: it has " + pixels.describe());
  const GazeWindow window = place_gaze_window(image.width_px, image.height_px, gaze_x, gaze_y, psf.size_px, options);
  ImageRGBA out = image;
  const std::size_t count = static_cast<std::size_t>(image.width_px) * image.height_px;
  std::vector<double> plane(count);
  for (int c = 0; c < 3; ++c) {
    for (std::size_t k = 0; k < count; ++k) plane[k] = image.rgba[4 * k + static_cast<std::size_t>(c)];
    const auto windowed = convolve_gaze_window_plane(plane, image.width_px, image.height_px, psf,
                                                     psf.channels == 3 ? c : 0, window, options.convolution, report);
    const auto blended = blend_gaze_window_plane(plane, image.width_px, image.height_px, windowed, window);
    for (std::size_t k = 0; k < count; ++k) out.rgba[4 * k + static_cast<std::size_t>(c)] = static_cast<float>(blended[k]);
  }
  return out;
}

}  // namespace glarelab

#include "glare/analytic/display_psf_image.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace glarelab {
namespace {

constexpr double kFlatDistanceMm = 1000.0;

void normalise_channels(Psf& psf) {
  const std::size_t count = static_cast<std::size_t>(psf.size_px) * psf.size_px;
  for (int c = 0; c < psf.channels; ++c) {
    double sum = 0.0;
    for (std::size_t k = 0; k < count; ++k) sum += psf.values[c * count + k];
    if (!(sum > 0.0)) throw std::invalid_argument("the PSF image holds no light in channel " + std::to_string(c));
    for (std::size_t k = 0; k < count; ++k) psf.values[c * count + k] /= sum;
  }
}

void check_kernel_covers(const DisplayKernel& kernel, int size_px) {
  if (size_px % 2 != 0 || size_px < 2 || kernel.half_width_px < size_px / 2 || kernel.half_height_px < size_px / 2)
    throw std::invalid_argument("a " + std::to_string(size_px) + " px PSF image needs an even side and a kernel of half sizes " +
                                std::to_string(size_px / 2));
}

}  // namespace

DisplayGeometry flat_display_geometry(double degrees_per_pixel) {
  return {kFlatDistanceMm, kFlatDistanceMm * std::tan(degrees_per_pixel * std::numbers::pi / 180.0)};
}

Psf analytic_psf_image(const AnalyticPsf& psf, double degrees_per_pixel, int size_px, int threads) {
  const int half = size_px / 2;
  const DisplayKernel kernel = analytic_display_kernel(psf, flat_display_geometry(degrees_per_pixel), half, half, threads);
  check_kernel_covers(kernel, size_px);
  Psf image;
  image.size_px = size_px;
  image.degrees_per_pixel = degrees_per_pixel;
  image.channels = kernel.channels;
  image.values.assign(static_cast<std::size_t>(image.channels) * size_px * size_px, 0.0);
  for (int c = 0; c < image.channels; ++c)
    for (int y = 0; y < size_px; ++y)
      for (int x = 0; x < size_px; ++x) image.at(c, x, y) = kernel.at(c, x - half, y - half);
  normalise_channels(image);
  return image;
}

Psf hybrid_psf_image(const Psf& near, const DisplayKernel& far, double degrees_per_pixel, int size_px) {
  check_kernel_covers(far, size_px);
  const int half = size_px / 2, near_centre = near.size_px / 2;
  Psf image;
  image.size_px = size_px;
  image.degrees_per_pixel = degrees_per_pixel;
  image.channels = 3;
  image.values.assign(3 * static_cast<std::size_t>(size_px) * size_px, 0.0);
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < size_px; ++y)
      for (int x = 0; x < size_px; ++x) {
        const int dx = x - half, dy = y - half;
        const int nx = near_centre + dx, ny = near_centre + dy;
        const bool on_near = nx >= 0 && ny >= 0 && nx < near.size_px && ny < near.size_px;
        image.at(c, x, y) = (on_near ? near.at(near.channels == 1 ? 0 : c, nx, ny) : 0.0) +
                            far.at(far.channels == 1 ? 0 : c, dx, dy);
      }
  normalise_channels(image);
  return image;
}

}  // namespace glarelab

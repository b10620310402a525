#include "glare/analytic/pixel_solid_angle.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace glarelab {

PixelSolidAngle::PixelSolidAngle(const DisplayGeometry& geometry, int width_px, int height_px)
    : width_px_(width_px), height_px_(height_px), relative_(static_cast<std::size_t>(width_px) * height_px) {
  if (!(geometry.viewing_distance_mm > 0.0) || !(geometry.pixel_pitch_mm > 0.0))
    throw std::invalid_argument("pixel solid angle: viewing distance and pixel pitch must be positive (got " +
                                std::to_string(geometry.viewing_distance_mm) + " mm, " +
                                std::to_string(geometry.pixel_pitch_mm) + " mm)");
  const double d2 = geometry.viewing_distance_mm * geometry.viewing_distance_mm;
  for (int y = 0; y < height_px; ++y) {
    const double y_mm = (y + 0.5 - 0.5 * height_px) * geometry.pixel_pitch_mm;
    for (int x = 0; x < width_px; ++x) {
      const double x_mm = (x + 0.5 - 0.5 * width_px) * geometry.pixel_pitch_mm;
      const double r2 = d2 + x_mm * x_mm + y_mm * y_mm;
      relative_[static_cast<std::size_t>(y) * width_px + x] = static_cast<float>(std::pow(d2 / r2, 1.5));
    }
  }
}

namespace {
void check_size(const ImageRGBA& image, int width_px, int height_px) {
  if (image.width_px != width_px || image.height_px != height_px)
    throw std::invalid_argument("pixel solid angle: frame " + std::to_string(image.width_px) + " x " +
                                std::to_string(image.height_px) + " px, weights for " + std::to_string(width_px) +
                                " x " + std::to_string(height_px));
}
}  // namespace

ImageRGBA PixelSolidAngle::to_energy(const ImageRGBA& luminance) const {
  check_size(luminance, width_px_, height_px_);
  ImageRGBA energy = luminance;
  for (std::size_t i = 0; i < relative_.size(); ++i)
    for (int c = 0; c < 3; ++c) energy.rgba[4 * i + c] *= relative_[i];
  return energy;
}

void PixelSolidAngle::to_luminance(ImageRGBA& energy) const {
  check_size(energy, width_px_, height_px_);
  for (std::size_t i = 0; i < relative_.size(); ++i)
    for (int c = 0; c < 3; ++c) energy.rgba[4 * i + c] /= relative_[i];
}

}  // namespace glarelab

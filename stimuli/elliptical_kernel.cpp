#include "stimuli/elliptical_kernel.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace glarelab {
namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

}  // namespace

PixelBlurEllipse pixel_blur_ellipse(const DioptricPower& error, double pupil_radius_m, double degrees_per_pixel) {
  const BlurEllipse angular = geometric_blur_ellipse(error, pupil_radius_m);
  const double radians_per_pixel = degrees_per_pixel * kRadPerDeg;
  return {angular.semi_major_rad / radians_per_pixel, angular.semi_minor_rad / radians_per_pixel,
          angular.major_axis_angle_deg};
}

int EllipticalKernel::nonzero_taps() const {
  return static_cast<int>(std::count_if(weights.begin(), weights.end(), [](double w) { return w != 0.0; }));
}

EllipticalKernel elliptical_kernel(const PixelBlurEllipse& ellipse, int subsamples_per_axis) {
  if (subsamples_per_axis < 1 || !std::isfinite(ellipse.semi_major_px) || !std::isfinite(ellipse.semi_minor_px) ||
      ellipse.semi_minor_px < 0.0 || ellipse.semi_major_px < ellipse.semi_minor_px)
    throw std::invalid_argument("stimuli/elliptical_kernel: semi-axes " + std::to_string(ellipse.semi_major_px) +
                                " and " + std::to_string(ellipse.semi_minor_px) +
                                " px (major >= minor >= 0, finite) with " + std::to_string(subsamples_per_axis) +
                                " subsamples a side (>= 1) do not describe a kernel");
  const double spacing_px = 1.0 / subsamples_per_axis;
  const double a = std::max(ellipse.semi_major_px, spacing_px);
  const double b = std::max(ellipse.semi_minor_px, spacing_px);
  const double cos_t = std::cos(ellipse.major_axis_angle_deg * kRadPerDeg);
  const double sin_t = std::sin(ellipse.major_axis_angle_deg * kRadPerDeg);
  // Half-widths of the ellipse's bounding box; a tap is needed where its pixel square reaches it.
  const double half_x = std::hypot(a * cos_t, b * sin_t);
  const double half_y = std::hypot(a * sin_t, b * cos_t);
  EllipticalKernel kernel;
  kernel.radius_x_px = std::max(0, static_cast<int>(std::ceil(half_x + 0.5)) - 1);
  kernel.radius_y_px = std::max(0, static_cast<int>(std::ceil(half_y + 0.5)) - 1);
  kernel.weights.assign(static_cast<std::size_t>(kernel.width()) * kernel.height(), 0.0);
  const double inv_a2 = 1.0 / (a * a), inv_b2 = 1.0 / (b * b);
  const double sample_area = spacing_px * spacing_px;
  double total = 0.0;
  for (int dy = -kernel.radius_y_px; dy <= kernel.radius_y_px; ++dy) {
    for (int dx = -kernel.radius_x_px; dx <= kernel.radius_x_px; ++dx) {
      int inside = 0;
      for (int j = 0; j < subsamples_per_axis; ++j) {
        // Image rows run down: the observer-frame y of a point is minus its image y.
        const double y_up = -(dy - 0.5 + (j + 0.5) * spacing_px);
        for (int i = 0; i < subsamples_per_axis; ++i) {
          const double x = dx - 0.5 + (i + 0.5) * spacing_px;
          const double along = x * cos_t + y_up * sin_t;
          const double across = -x * sin_t + y_up * cos_t;
          if (along * along * inv_a2 + across * across * inv_b2 <= 1.0) ++inside;
        }
      }
      const double coverage = inside * sample_area;
      kernel.weights[static_cast<std::size_t>((dy + kernel.radius_y_px) * kernel.width() + dx + kernel.radius_x_px)] =
          coverage;
      total += coverage;
    }
  }
  kernel.covered_area_px2 = total;
  if (total <= 0.0) {  // cannot happen with the widening above; kept so a kernel is never empty
    kernel.weights[static_cast<std::size_t>(kernel.radius_y_px * kernel.width() + kernel.radius_x_px)] = 1.0;
    return kernel;
  }
  for (double& w : kernel.weights) w /= total;
  return kernel;
}

}  // namespace glarelab

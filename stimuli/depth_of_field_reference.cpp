#include "stimuli/depth_of_field_reference.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "stimuli/elliptical_kernel.h"

namespace glarelab {

ImageRGBA depth_of_field_reference(const ImageRGBA& image_cd_m2, const std::vector<float>& depth_m,
                                   const DepthOfFieldSettings& settings) {
  check_depth_of_field_inputs(image_cd_m2, depth_m, settings);
  const int width = image_cd_m2.width_px, height = image_cd_m2.height_px;
  std::map<float, EllipticalKernel> kernels;  // by depth: each distinct depth's exact blur
  std::vector<double> sums(4 * static_cast<std::size_t>(width) * height, 0.0);  // R, G, B, weight
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float depth = depth_m[static_cast<std::size_t>(y) * width + x];
      auto found = kernels.find(depth);
      if (found == kernels.end()) {
        const DioptricPower error = settings.residual_error(static_cast<double>(depth));
        found = kernels
                    .emplace(depth, elliptical_kernel(
                                        pixel_blur_ellipse(error, settings.pupil_radius_m, settings.degrees_per_pixel)))
                    .first;
      }
      const EllipticalKernel& kernel = found->second;
      const float* source = image_cd_m2.pixel(x, y);
      for (int dy = -kernel.radius_y_px; dy <= kernel.radius_y_px; ++dy) {
        const int ty = y + dy;
        if (ty < 0 || ty >= height) continue;
        for (int dx = -kernel.radius_x_px; dx <= kernel.radius_x_px; ++dx) {
          const int tx = x + dx;
          const double w = kernel.at(dx, dy);
          if (tx < 0 || tx >= width || w == 0.0) continue;
          double* target = &sums[4 * (static_cast<std::size_t>(ty) * width + tx)];
          target[0] += w * source[0];
          target[1] += w * source[1];
          target[2] += w * source[2];
          target[3] += w;
        }
      }
    }
  ImageRGBA result = image_cd_m2;
  for (std::size_t k = 0; k < static_cast<std::size_t>(width) * height; ++k) {
    const double* sum = &sums[4 * k];
    const double weight = sum[3] > 0.0 ? sum[3] : 1.0;  // every pixel keeps part of its own light
    for (int c = 0; c < 3; ++c) result.rgba[4 * k + c] = static_cast<float>(sum[c] / weight);
  }
  return result;
}

DepthOfFieldError depth_of_field_error(const ImageRGBA& result, const ImageRGBA& reference) {
  if (result.width_px != reference.width_px || result.height_px != reference.height_px)
    throw std::invalid_argument("stimuli/depth_of_field_reference: comparing a " + std::to_string(result.width_px) +
                                " x " + std::to_string(result.height_px) + " px result with a " +
                                std::to_string(reference.width_px) + " x " + std::to_string(reference.height_px) +
                                " px reference");
  DepthOfFieldError error;
  double reference_sum = 0.0;
  std::size_t values = 0;
  for (std::size_t k = 0; k < result.rgba.size(); k += 4)
    for (std::size_t c = 0; c < 3; ++c) {
      const double difference = std::abs(static_cast<double>(result.rgba[k + c]) - reference.rgba[k + c]);
      error.max_abs_cd_m2 = std::max(error.max_abs_cd_m2, difference);
      error.mean_abs_cd_m2 += difference;
      reference_sum += std::abs(static_cast<double>(reference.rgba[k + c]));
      ++values;
    }
  if (values > 0) error.mean_abs_cd_m2 /= static_cast<double>(values);
  const double reference_mean = values > 0 ? reference_sum / static_cast<double>(values) : 0.0;
  error.mean_relative = reference_mean > 0.0 ? error.mean_abs_cd_m2 / reference_mean : 0.0;
  return error;
}

}  // namespace glarelab

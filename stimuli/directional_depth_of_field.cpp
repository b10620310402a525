// Depth of field with an error that depends on the line of sight, per display region
// (stimuli/directional_depth_of_field.h).
#include "stimuli/directional_depth_of_field.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "stimuli/depth_layers.h"

namespace glarelab {
namespace {

// The edges of n equal parts of [0, size): part i is [edges[i], edges[i + 1]).
std::vector<int> split(int size, int parts) {
  std::vector<int> edges(static_cast<std::size_t>(parts) + 1);
  for (int i = 0; i <= parts; ++i)
    edges[static_cast<std::size_t>(i)] = static_cast<int>(static_cast<long long>(size) * i / parts);
  return edges;
}

struct Span {
  int begin = 0, end = 0;  // [begin, end)
  double centre() const { return 0.5 * (begin + end - 1); }
};

// The nearest and farthest depth of the scene (+inf allowed): the blur is affine in vergence, so
// its spectral norm (and the difference of two such errors) is largest at one of them.
std::array<double, 2> extreme_depths_m(const std::vector<float>& depth_m) {
  const auto [low, high] = std::minmax_element(depth_m.begin(), depth_m.end());
  return {static_cast<double>(*low), static_cast<double>(*high)};
}

class RegionPlanner {
 public:
  RegionPlanner(const ImageRGBA& image, const std::array<double, 2>& depths, const DirectionalDepthOfFieldSettings& s)
      : width_(image.width_px), height_(image.height_px), depths_(depths), settings_(s),
        geometry_{s.degrees_per_pixel, s.pupil_radius_m} {}

  // The largest blur error, at both extreme depths, between the error at a region's centre and at
  // the given points of each region (pixel offsets from its first pixel: -1 means the last).
  double worst(int nx, int ny, bool along_x, bool along_y) const {
    const std::vector<int> xs = split(width_, nx), ys = split(height_, ny);
    double largest = 0.0;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Span sx{xs[static_cast<std::size_t>(i)], xs[static_cast<std::size_t>(i) + 1]};
        const Span sy{ys[static_cast<std::size_t>(j)], ys[static_cast<std::size_t>(j) + 1]};
        const EyeErrorAtDistance centre = settings_.residual_error(sx.centre(), sy.centre());
        std::vector<std::array<double, 2>> points;
        if (along_x && !along_y) points = {{double(sx.begin), sy.centre()}, {double(sx.end - 1), sy.centre()}};
        if (along_y && !along_x) points = {{sx.centre(), double(sy.begin)}, {sx.centre(), double(sy.end - 1)}};
        if (along_x && along_y)
          points = {{double(sx.begin), double(sy.begin)}, {double(sx.end - 1), double(sy.begin)},
                    {double(sx.begin), double(sy.end - 1)}, {double(sx.end - 1), double(sy.end - 1)}};
        for (const auto& point : points) {
          const EyeErrorAtDistance there = settings_.residual_error(point[0], point[1]);
          for (const double depth : depths_)
            largest = std::max(largest, blur_error_px(centre(depth), there(depth), geometry_));
        }
      }
    return largest;
  }

 private:
  int width_, height_;
  std::array<double, 2> depths_;
  const DirectionalDepthOfFieldSettings& settings_;
  BlurGeometry geometry_;
};

}  // namespace

ImageRGBA apply_directional_depth_of_field(const ImageRGBA& image_cd_m2, const std::vector<float>& depth_m,
                                           const DirectionalDepthOfFieldSettings& settings,
                                           DirectionalDepthOfFieldReport* report) {
  if (settings.max_regions_per_axis < 1)
    throw std::invalid_argument("stimuli/directional_depth_of_field: max_regions_per_axis must be >= 1 (got " +
                                std::to_string(settings.max_regions_per_axis) + ")");
  if (!settings.residual_error)
    throw std::invalid_argument("stimuli/directional_depth_of_field: no error function given");
  DepthOfFieldSettings base;
  base.degrees_per_pixel = settings.degrees_per_pixel;
  base.pupil_radius_m = settings.pupil_radius_m;
  base.tolerance_px = settings.tolerance_px;
  base.threads = settings.threads;
  // The error along the frame centre's line of sight, so the inputs are checked as the one-region
  // stage would check them (an empty image is refused there first); each region below takes the
  // error along its own centre's.
  if (!image_cd_m2.empty())
    base.residual_error = settings.residual_error(Span{0, image_cd_m2.width_px}.centre(),
                                                  Span{0, image_cd_m2.height_px}.centre());
  check_depth_of_field_inputs(image_cd_m2, depth_m, base);

  const std::array<double, 2> depths = extreme_depths_m(depth_m);
  const RegionPlanner planner(image_cd_m2, depths, settings);
  // Halve the axes in turn while a region's edge is more than the tolerance off its centre.
  int nx = 1, ny = 1;
  const int cap_x = std::min(settings.max_regions_per_axis, image_cd_m2.width_px);
  const int cap_y = std::min(settings.max_regions_per_axis, image_cd_m2.height_px);
  for (;;) {
    bool changed = false;
    if (nx < cap_x && planner.worst(nx, ny, true, false) > settings.tolerance_px) nx = std::min(2 * nx, cap_x), changed = true;
    if (ny < cap_y && planner.worst(nx, ny, false, true) > settings.tolerance_px) ny = std::min(2 * ny, cap_y), changed = true;
    if (!changed) break;
  }

  DirectionalDepthOfFieldReport out;
  out.regions_x = nx;
  out.regions_y = ny;
  out.max_direction_error_px = planner.worst(nx, ny, true, true);
  const BlurGeometry geometry{settings.degrees_per_pixel, settings.pupil_radius_m};
  const std::vector<int> xs = split(image_cd_m2.width_px, nx), ys = split(image_cd_m2.height_px, ny);
  ImageRGBA result = image_cd_m2;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const Span sx{xs[static_cast<std::size_t>(i)], xs[static_cast<std::size_t>(i) + 1]};
      const Span sy{ys[static_cast<std::size_t>(j)], ys[static_cast<std::size_t>(j) + 1]};
      DepthOfFieldSettings region = base;
      region.residual_error = settings.residual_error(sx.centre(), sy.centre());
      DepthOfFieldReport layers;
      if (nx == 1 && ny == 1) {
        result = apply_depth_of_field(image_cd_m2, depth_m, region, &layers);
      } else {
        // The largest blur of the region's error at the scene's depths, plus two pixels: the
        // kernel's antialiased rim and the widening of a line focus (stimuli/elliptical_kernel.h).
        double reach_px = 0.0;
        for (const double depth : depths)
          reach_px = std::max(reach_px, blur_error_px(region.residual_error(depth), DioptricPower{}, geometry));
        const int margin = static_cast<int>(std::ceil(reach_px)) + 2;
        out.margin_px = std::max(out.margin_px, margin);
        const int x0 = std::max(0, sx.begin - margin), x1 = std::min(image_cd_m2.width_px, sx.end + margin);
        const int y0 = std::max(0, sy.begin - margin), y1 = std::min(image_cd_m2.height_px, sy.end + margin);
        ImageRGBA crop(x1 - x0, y1 - y0);
        std::vector<float> crop_depth(static_cast<std::size_t>(crop.width_px) * static_cast<std::size_t>(crop.height_px));
        for (int y = y0; y < y1; ++y) {
          std::copy_n(image_cd_m2.pixel(x0, y), 4 * crop.width_px, crop.pixel(0, y - y0));
          std::copy_n(depth_m.begin() + static_cast<std::ptrdiff_t>(y) * image_cd_m2.width_px + x0, crop.width_px,
                      crop_depth.begin() + static_cast<std::ptrdiff_t>(y - y0) * crop.width_px);
        }
        const ImageRGBA blurred = apply_depth_of_field(crop, crop_depth, region, &layers);
        for (int y = sy.begin; y < sy.end; ++y)
          std::copy_n(blurred.pixel(sx.begin - x0, y - y0), 4 * (sx.end - sx.begin), result.pixel(sx.begin, y));
      }
      out.layers += layers.layers;
      out.most_layers_in_a_region = std::max(out.most_layers_in_a_region, layers.layers);
      out.max_layer_error_px = std::max(out.max_layer_error_px, layers.max_blur_error_px);
    }
  if (report != nullptr) *report = out;
  return result;
}

}  // namespace glarelab

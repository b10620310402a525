#include "stimuli/scene_fit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace glarelab {
namespace {

// For each output index, the input indices its box covers and their weights (the covered
// fraction of each input pixel, divided by the box's length so the weights sum to 1).
struct BoxTap {
  int index = 0;
  double weight = 0.0;
};

std::vector<std::vector<BoxTap>> box_taps(int input_px, int output_px) {
  std::vector<std::vector<BoxTap>> taps(static_cast<std::size_t>(output_px));
  const double box = static_cast<double>(input_px) / output_px;
  for (int o = 0; o < output_px; ++o) {
    const double from = o * box, to = (o + 1) * box;
    for (int i = static_cast<int>(std::floor(from)); i < input_px && i < to; ++i) {
      const double covered = std::min(to, i + 1.0) - std::max(from, static_cast<double>(i));
      if (covered > 0.0) taps[static_cast<std::size_t>(o)].push_back({i, covered / box});
    }
  }
  return taps;
}

}  // namespace

FitSize scaled_fit_size(int width_px, int height_px, int max_width_px, int max_height_px) {
  if (width_px <= max_width_px && height_px <= max_height_px) return {width_px, height_px};
  const double scale = std::min(static_cast<double>(max_width_px) / width_px, static_cast<double>(max_height_px) / height_px);
  // Rounded down (with a margin for the division's rounding), so the result never exceeds its place.
  const auto side = [scale](int px, int max_px) {
    return std::clamp(static_cast<int>(std::floor(px * scale + 1e-9)), 1, std::max(1, max_px));
  };
  return {side(width_px, max_width_px), side(height_px, max_height_px)};
}

ImageRGBA scale_image_down(const ImageRGBA& image, int width_px, int height_px) {
  if (width_px < 1 || height_px < 1 || width_px > image.width_px || height_px > image.height_px)
    throw std::invalid_argument("scale_image_down: " + std::to_string(width_px) + " x " + std::to_string(height_px) +
                                " px is not a reduction of " + std::to_string(image.width_px) + " x " +
                                std::to_string(image.height_px) + " px");
  if (!image.depth.empty())
    throw std::invalid_argument("a scene with a depth (Z) channel cannot be scaled: averaging depths across an edge "
                                "makes surfaces that are not there; use fit = \"crop\" or a smaller image");
  const auto columns = box_taps(image.width_px, width_px);
  const auto rows = box_taps(image.height_px, height_px);
  // Rows first (into doubles), then columns: separable, so each output is the box's exact mean.
  std::vector<double> narrow(static_cast<std::size_t>(image.height_px) * static_cast<std::size_t>(width_px) * 4, 0.0);
  for (int y = 0; y < image.height_px; ++y)
    for (int x = 0; x < width_px; ++x)
      for (const BoxTap& tap : columns[static_cast<std::size_t>(x)])
        for (int c = 0; c < 4; ++c)
          narrow[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width_px) + static_cast<std::size_t>(x)) * 4 +
                 static_cast<std::size_t>(c)] += tap.weight * image.pixel(tap.index, y)[c];
  ImageRGBA scaled(width_px, height_px, 0.0f);
  for (int y = 0; y < height_px; ++y)
    for (int x = 0; x < width_px; ++x)
      for (int c = 0; c < 4; ++c) {
        double sum = 0.0;
        for (const BoxTap& tap : rows[static_cast<std::size_t>(y)])
          sum += tap.weight * narrow[(static_cast<std::size_t>(tap.index) * static_cast<std::size_t>(width_px) +
                                      static_cast<std::size_t>(x)) * 4 + static_cast<std::size_t>(c)];
        scaled.pixel(x, y)[c] = static_cast<float>(sum);
      }
  return scaled;
}

ImageRGBA crop_image_centre(const ImageRGBA& image, int width_px, int height_px) {
  width_px = std::clamp(width_px, 1, image.width_px);
  height_px = std::clamp(height_px, 1, image.height_px);
  const int x0 = (image.width_px - width_px) / 2, y0 = (image.height_px - height_px) / 2;
  ImageRGBA cropped(width_px, height_px, 0.0f);
  for (int y = 0; y < height_px; ++y)
    std::copy_n(image.pixel(x0, y0 + y), 4 * static_cast<std::size_t>(width_px), cropped.pixel(0, y));
  if (!image.depth.empty()) {
    cropped.depth.resize(static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px));
    for (int y = 0; y < height_px; ++y)
      std::copy_n(image.depth.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y0 + y) * image.width_px + x0),
                  width_px, cropped.depth.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * width_px));
  }
  return cropped;
}

}  // namespace glarelab

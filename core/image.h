#pragma once
// A linear floating-point image in memory: interleaved RGBA, row 0 at the top.
// Scene images hold luminance-calibrated linear Rec.709 RGB whose Y is in cd/m2 (D65 white).
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace glarelab {

struct ImageRGBA {
  int width_px = 0;
  int height_px = 0;
  std::vector<float> rgba;  // size 4 * width_px * height_px
  // Optional depth channel (EXR "Z"), one value per pixel, empty when absent.
  std::vector<float> depth;

  ImageRGBA() = default;
  ImageRGBA(int width, int height, float fill = 0.0f);
  float* pixel(int x, int y) { return &rgba[4 * (static_cast<std::size_t>(y) * width_px + x)]; }
  const float* pixel(int x, int y) const { return &rgba[4 * (static_cast<std::size_t>(y) * width_px + x)]; }
  bool empty() const { return width_px == 0 || height_px == 0; }
};

// Rec.709 / sRGB primaries, D65: relative luminance Y from linear RGB (ITU-R BT.709-6, item 3.2).
inline double luminance_rec709(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

// Counts of pixels that cannot be luminances; used to refuse or report on input images.
struct NonFiniteReport {
  std::size_t nan_pixels = 0;
  std::size_t inf_pixels = 0;
  std::size_t negative_pixels = 0;
  bool clean() const { return nan_pixels == 0 && inf_pixels == 0 && negative_pixels == 0; }
  std::string describe() const;
};
NonFiniteReport inspect_pixels(const ImageRGBA& image);

// Largest luminance Y (cd/m2 for a calibrated image) over all pixels.
double max_luminance(const ImageRGBA& image);
double mean_luminance(const ImageRGBA& image);

}  // namespace glarelab

#include "stimuli/overlay_image.h"

#include <algorithm>
#include <cstdlib>

#include "stimuli/text_image.h"

namespace glarelab {

ImageRGBA text_overlay(const std::string& utf8_text, double line_height_px, double max_width_px, double text_cd_m2) {
  TextImageStyle style;
  style.line_height_px = line_height_px;
  style.max_width_px = max_width_px;
  // White on black: each pixel's value is the glyph coverage.
  style.text_cd_m2 = 1.0;
  style.background_cd_m2 = 0.0;
  return overlay_from_coverage(render_text_image(utf8_text, style), text_cd_m2);
}

ImageRGBA overlay_from_coverage(const ImageRGBA& coverage, double luminance_cd_m2) {
  ImageRGBA overlay(coverage.width_px, coverage.height_px);
  const auto luminance = static_cast<float>(luminance_cd_m2);
  for (std::size_t i = 0; i < coverage.rgba.size(); i += 4) {
    const float alpha = std::clamp(coverage.rgba[i], 0.0f, 1.0f);
    overlay.rgba[i] = overlay.rgba[i + 1] = overlay.rgba[i + 2] = luminance * alpha;
    overlay.rgba[i + 3] = alpha;
  }
  return overlay;
}

ImageRGBA fixation_cross(int size_px, double luminance_cd_m2) {
  const int size = std::max(3, size_px | 1);
  const int thickness = std::max(1, size / 8) | 1;
  const int centre = size / 2;
  ImageRGBA cross(size, size);
  const auto luminance = static_cast<float>(luminance_cd_m2);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const bool on = std::abs(x - centre) <= thickness / 2 || std::abs(y - centre) <= thickness / 2;
      float* pixel = &cross.rgba[(static_cast<std::size_t>(y) * static_cast<std::size_t>(size) + static_cast<std::size_t>(x)) * 4];
      pixel[0] = pixel[1] = pixel[2] = on ? luminance : 0.0f;
      pixel[3] = on ? 1.0f : 0.0f;
    }
  }
  return cross;
}

PixelRect centred_rect(int width_px, int height_px, int screen_width_px, int screen_height_px) {
  return {(screen_width_px - width_px) / 2, (screen_height_px - height_px) / 2, width_px, height_px};
}

PixelRect rect_above(const std::vector<PixelRect>& stimuli, int width_px, int height_px, int screen_width_px,
                     int screen_height_px, int gap_px) {
  if (stimuli.empty()) return centred_rect(width_px, height_px, screen_width_px, screen_height_px);
  int top = screen_height_px;
  for (const PixelRect& rect : stimuli) top = std::min(top, rect.y_px);
  return {(screen_width_px - width_px) / 2, std::max(0, top - gap_px - height_px), width_px, height_px};
}

}  // namespace glarelab

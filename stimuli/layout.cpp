#include "stimuli/layout.h"

#include <algorithm>
#include <stdexcept>

namespace glarelab {

std::vector<PixelRect> side_by_side_layout(int screen_width_px, int screen_height_px,
                                           const std::vector<PixelRect>& image_sizes, std::vector<PixelRect>* columns) {
  if (image_sizes.empty()) throw std::invalid_argument("side_by_side_layout: no images");
  const int count = static_cast<int>(image_sizes.size());
  std::vector<PixelRect> placed;
  for (int i = 0; i < count; ++i) {
    // Integer column edges that tile the screen exactly.
    const int left = screen_width_px * i / count;
    const int right = screen_width_px * (i + 1) / count;
    const PixelRect column{left, 0, right - left, screen_height_px};
    if (columns) columns->push_back(column);
    const PixelRect& size = image_sizes[static_cast<std::size_t>(i)];
    placed.push_back({column.x_px + (column.width_px - size.width_px) / 2, (screen_height_px - size.height_px) / 2,
                      size.width_px, size.height_px});
  }
  return placed;
}

PixelRect intersection(const PixelRect& a, const PixelRect& b) {
  const int x0 = std::max(a.x_px, b.x_px), y0 = std::max(a.y_px, b.y_px);
  const int x1 = std::min(a.x_px + a.width_px, b.x_px + b.width_px);
  const int y1 = std::min(a.y_px + a.height_px, b.y_px + b.height_px);
  if (x1 <= x0 || y1 <= y0) return PixelRect{a.x_px, a.y_px, 0, 0};
  return PixelRect{x0, y0, x1 - x0, y1 - y0};
}

}  // namespace glarelab

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

}  // namespace glarelab

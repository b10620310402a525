#include "stimuli/layout.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace glarelab {

std::vector<PixelRect> side_by_side_layout(int screen_width_px, int screen_height_px,
                                           const std::vector<PixelRect>& image_sizes, std::vector<PixelRect>* columns,
                                           int gap_px) {
  if (image_sizes.empty()) throw std::invalid_argument("side_by_side_layout: no images");
  const int count = static_cast<int>(image_sizes.size());
  const int shared_px = screen_width_px - (count - 1) * gap_px;  // the columns' widths together
  if (gap_px < 0 || shared_px < count)
    throw std::invalid_argument("side_by_side_layout: a gap of " + std::to_string(gap_px) + " px leaves no column for " +
                                std::to_string(count) + " images on " + std::to_string(screen_width_px) + " px");
  std::vector<PixelRect> placed;
  for (int i = 0; i < count; ++i) {
    // Integer column edges that tile the screen less its gaps exactly.
    const int left = shared_px * i / count + i * gap_px;
    const int right = shared_px * (i + 1) / count + i * gap_px;
    const PixelRect column{left, 0, right - left, screen_height_px};
    if (columns) columns->push_back(column);
    const PixelRect& size = image_sizes[static_cast<std::size_t>(i)];
    placed.push_back({column.x_px + (column.width_px - size.width_px) / 2, (screen_height_px - size.height_px) / 2,
                      size.width_px, size.height_px});
  }
  return placed;
}

}  // namespace glarelab

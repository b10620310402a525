#pragma once
// Where stimuli go on the screen. Scenes are shown at their native pixel size (one image pixel on
// one display pixel) so their angular size follows from the display geometry alone.
#include <vector>

namespace glarelab {

struct PixelRect {
  int x_px = 0;  // left
  int y_px = 0;  // top
  int width_px = 0;
  int height_px = 0;
  bool empty() const { return width_px <= 0 || height_px <= 0; }
};

// The pixels two rectangles share (0 x 0 at the first one's corner when none).
PixelRect intersection(const PixelRect& a, const PixelRect& b);

// `count` images of the given sizes side by side: the screen is split into equal columns and each
// image is centred in its column. An image larger than its column is centred and cropped by the
// column (the returned rect may extend past the column; the renderer clips it with a scissor).
std::vector<PixelRect> side_by_side_layout(int screen_width_px, int screen_height_px,
                                           const std::vector<PixelRect>& image_sizes, std::vector<PixelRect>* columns);

}  // namespace glarelab

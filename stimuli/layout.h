#pragma once
// Where stimuli go on the screen. Scenes are shown at their native pixel size (one image pixel on
// one display pixel) so their angular size follows from the display geometry alone.
#include <vector>

#include "core/pixel_rect.h"

namespace glarelab {

// `count` images of the given sizes side by side: the screen's width less (count - 1) gaps of
// `gap_px` is split into equal columns (integer edges, column i starting at
// i (W - (n - 1) g) / n + i g), each as tall as the screen, and each image is centred in its
// column. An image larger than its column is centred and cropped by the column (the returned rect
// may extend past the column; the renderer clips it with a scissor); sessions refuse, scale or crop
// such scenes before (runner/session/scene_places.h), so that nothing is cut silently.
std::vector<PixelRect> side_by_side_layout(int screen_width_px, int screen_height_px,
                                           const std::vector<PixelRect>& image_sizes, std::vector<PixelRect>* columns,
                                           int gap_px = 0);

}  // namespace glarelab

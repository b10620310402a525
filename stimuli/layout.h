#pragma once
// Where stimuli go on the screen. Scenes are shown at their native pixel size (one image pixel on
// one display pixel) so their angular size follows from the display geometry alone.
#include <vector>

#include "core/pixel_rect.h"

namespace glarelab {

// `count` images of the given sizes side by side: the screen is split into equal columns and each
// image is centred in its column. An image larger than its column is centred and cropped by the
// column (the returned rect may extend past the column; the renderer clips it with a scissor).
std::vector<PixelRect> side_by_side_layout(int screen_width_px, int screen_height_px,
                                           const std::vector<PixelRect>& image_sizes, std::vector<PixelRect>* columns);

}  // namespace glarelab

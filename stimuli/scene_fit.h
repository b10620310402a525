#pragma once
// A scene made to fit its place on the display ([scenes] fit = "scale" or "crop",
// docs/EXPERIMENT_FILES.md, "Placement"): scaled down whole, or cut about its centre.
#include "core/image.h"

namespace glarelab {

// The largest size with the image's aspect (to the pixel, rounded down) that fits within
// max_width_px x max_height_px; the image's own size when it fits already. At least 1 x 1.
struct FitSize {
  int width_px = 0;
  int height_px = 0;
};
FitSize scaled_fit_size(int width_px, int height_px, int max_width_px, int max_height_px);

// The image resampled to width_px x height_px (no larger than it) by area averaging: each output
// pixel is the mean of the input area it covers (a box of w / w' x h / h' input pixels, partial
// pixels by their covered fraction). The boxes tile the input, so the mean luminance, and the
// luminance per degree squared of each region, is that of the original: a light's energy is
// kept, spread over fewer pixels. Alpha is averaged alike. An image with a depth channel is refused
// (std::invalid_argument): averaging depths across an edge makes surfaces that are not there.
ImageRGBA scale_image_down(const ImageRGBA& image, int width_px, int height_px);

// The centred width_px x height_px part of the image (each side at most the image's; the left
// and top margins are half the excess, rounded down, as side_by_side_layout centres), with its
// depth channel.
ImageRGBA crop_image_centre(const ImageRGBA& image, int width_px, int height_px);

}  // namespace glarelab

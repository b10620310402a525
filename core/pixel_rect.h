#pragma once
// A rectangle of pixels on an image or the display: where a scene is placed, what of a frame glare
// can change, an eye's half of a stereo frame. One convention everywhere: half-open, the pixels
// (x, y) with x_px <= x < x_px + width_px and y_px <= y < y_px + height_px, row 0 at the top
// (ImageRGBA's order; GL's bottom-up rows are converted where GL is called). A rectangle with no
// width or no height holds no pixel, wherever its corner lies.
#include <vector>

#include "core/image.h"

namespace glarelab {

struct PixelRect {
  int x_px = 0;  // left column
  int y_px = 0;  // top row
  int width_px = 0;
  int height_px = 0;

  int right_px() const { return x_px + width_px; }    // the first column past it
  int bottom_px() const { return y_px + height_px; }  // the first row past it
  bool empty() const { return width_px <= 0 || height_px <= 0; }
  // Whether `inner` lies within this rectangle, edges included (an empty one too, by its edges).
  bool contains(const PixelRect& inner) const {
    return inner.x_px >= x_px && inner.y_px >= y_px && inner.right_px() <= right_px() &&
           inner.bottom_px() <= bottom_px();
  }
  bool operator==(const PixelRect&) const = default;
};

// The whole image: {0, 0, width, height}.
PixelRect image_rect(const ImageRGBA& image);

// The pixels two rectangles share; none (0 x 0 at the first one's corner) when they are apart or
// only touch along an edge.
PixelRect intersection(const PixelRect& a, const PixelRect& b);

// The smallest rectangle holding every pixel of both (or of all): the bounding box. Empty
// rectangles hold no pixel and are left out; with none left the result is {0, 0, 0, 0}.
PixelRect bounding_rect(const PixelRect& a, const PixelRect& b);
PixelRect bounding_rect(const std::vector<PixelRect>& rects);

// The part of `image` inside `rect` as an image of its own (clipped at the image's edges: the
// result is intersection(rect, image_rect(image)) in size, 0 x 0 when they share nothing). The
// depth channel comes along when the image has one.
ImageRGBA crop(const ImageRGBA& image, const PixelRect& rect);

// Writes `image` into `into` at `at` (the image's size, or std::invalid_argument), the pixels of
// `at` outside `into` left out. Depth is written where both images have it; otherwise `into`'s
// depth, if any, stays as it was.
void paste(ImageRGBA& into, const ImageRGBA& image, const PixelRect& at);

}  // namespace glarelab

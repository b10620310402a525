#pragma once
// Where a frame has light: the boxes around its non-black pixels (any of R, G, B not 0), split
// wherever an empty band of at least gap_px columns or rows runs across (a recursive X-Y cut). With
// gap_px >= the PSF's size M, the glare of one box (the box grown by M/2 before and M - 1 - M/2
// after) cannot reach another's, so each box can be convolved on its own and written back: the
// frame's glare is the sum of the boxes' glare (linearity; everything outside them is black) and
// those sums do not overlap. A stimulus of two rooms on a black display (the demo) then costs two
// small convolutions instead of one over both rooms and the black between them.
#include <vector>

#include "core/image.h"
#include "core/pixel_rect.h"

namespace glarelab {

// The boxes, each tight around its pixels, in no particular order but always the same for the
// same image; none when the image is all black. Separating bands are found on 8 x 8 pixel tiles,
// so a gap is only cut when at least gap_px empty columns (rows) are certain; more than
// max_boxes boxes give the one bounding box instead (many tiny lights: one convolution is cheaper).
std::vector<PixelRect> lit_regions(const ImageRGBA& image, int gap_px, int max_boxes = 16);

}  // namespace glarelab

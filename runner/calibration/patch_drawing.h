#pragma once
// Drawing a calibration patch straight into the display's default framebuffer: the drive values
// are the cleared colour, with no encoding, tone curve or dithering between them and the screen
// (the point of a calibration is to measure what a code does). The patch fills the screen or a
// centred rectangle on black (docs/DISPLAY_CALIBRATION.md, "Measuring a display").
#include <array>
#include <string>

#include "core/image.h"

namespace glarelab {

// Clears the display's frame (`framebuffer`: DisplayBackend::frame_framebuffer, 0 the default
// framebuffer; width_px x height_px) to black and the centred rectangle of `patch_fraction` of its
// width and height (1: the whole screen) to `rgb_drive`.
void draw_calibration_patch(int width_px, int height_px, double patch_fraction, const std::array<double, 3>& rgb_drive,
                            unsigned framebuffer = 0);

// The display's frame as drawn (before it is presented), drive values in [0, 1], row 0 at the top.
ImageRGBA read_default_framebuffer(int width_px, int height_px, unsigned framebuffer = 0);

}  // namespace glarelab

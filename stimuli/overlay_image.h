#pragma once
// Images drawn over a finished stimulus frame (FrameRenderer::compose_overlay): text and the
// fixation cross. They are seen on the display, not through the simulated eye, so they are drawn
// after glare. Overlay images are premultiplied: rgb = luminance (cd/m2) x coverage, alpha =
// coverage, so an antialiased glyph edge blends with whatever the frame shows beneath it.
#include <string>
#include <vector>

#include "core/image.h"
#include "core/pixel_rect.h"

namespace glarelab {

// Text in the luminance `text_cd_m2`, lines `line_height_px` high, wrapped at `max_width_px`
// (0: no wrapping), rasterised by stimuli/text_image.h.
ImageRGBA text_overlay(const std::string& utf8_text, double line_height_px, double max_width_px, double text_cd_m2);

// A coverage image (rgb = coverage in [0, 1], e.g. text rendered white on black) as an overlay of
// the given luminance.
ImageRGBA overlay_from_coverage(const ImageRGBA& coverage, double luminance_cd_m2);

// A plus sign `size_px` across (made odd so the cross has a centre pixel, at least 3), arms
// max(1, size / 8) pixels thick (odd), opaque in `luminance_cd_m2`, transparent elsewhere.
ImageRGBA fixation_cross(int size_px, double luminance_cd_m2);

// Where a block of `width_px` x `height_px` goes: centred horizontally, its bottom `gap_px` above
// the highest of the stimulus rectangles (clamped to the top of the screen). Without stimuli it is
// centred on the screen.
PixelRect rect_above(const std::vector<PixelRect>& stimuli, int width_px, int height_px, int screen_width_px,
                     int screen_height_px, int gap_px);
// Centred on the screen.
PixelRect centred_rect(int width_px, int height_px, int screen_width_px, int screen_height_px);

}  // namespace glarelab

#pragma once
// Per-eye views on one display ([display] stereo = "side_by_side", docs/STEREO.md): the left eye's
// view fills the left half of the frame and the right eye's the right half, as an HMD's mirror
// window or a side-by-side stereo display shows them. Each half is a display of its own to the
// eye that sees it (half the width, the same pixel pitch, viewing distance and photometry), so
// the layout, glare and perception stages of one eye are those of a mono display of that size.
// Eyes are named as eye trackers number them (Pupil Labs: eye 0 is the right eye, eye 1 the left).
#include <cstdint>
#include <string>
#include <vector>

#include "core/display_spec.h"
#include "core/image.h"
#include "stimuli/layout.h"

namespace glarelab {

struct EyeView {
  int tracker_eye = 0;  // the tracker's eye id: 0 right, 1 left (runner/tracker/tracker_source.h)
  std::string name;     // "left" | "right"
  PixelRect viewport;   // the eye's half of the frame (row 0 at the top)
};

const char* to_string(StereoMode mode);

// The eyes' views of a stereo display, left eye first; empty for StereoMode::none. The width must
// be even (protocols/ refuses an odd one), so both views have the same size.
std::vector<EyeView> stereo_eye_views(const DisplaySpec& display);

// The display an eye sees: its view's size, everything else the display's.
DisplaySpec eye_display(const DisplaySpec& display, const EyeView& view);

// The seed of an eye's model: drawn from the session seed on RandomStream::stereo_eye at the eye's
// tracker id, so the two eyes' particles, hippus and lids differ, deterministically.
std::uint64_t eye_seed(std::uint64_t session_seed, int tracker_eye);

// The images of one trial laid out for each eye as side_by_side_layout lays them out on a mono
// display of the view's size, moved into the view: the left eye's rects first, then the right
// eye's (2 x image_sizes). `columns` gets each rect's column, inside its view; `gap_px` is the
// background between columns (core/display_spec.h, stimulus_gap_px).
std::vector<PixelRect> stereo_layout(const std::vector<EyeView>& views, const std::vector<PixelRect>& image_sizes,
                                     std::vector<PixelRect>* columns, int gap_px = 0);

// Why `image_sizes` side by side do not fit an eye's view (an image wider or taller than its
// column there, which the other eye would otherwise lose to cropping), or empty when they fit.
// `names` names the images in the message.
std::string stereo_misfit(const DisplaySpec& display, const std::vector<PixelRect>& image_sizes,
                          const std::vector<std::string>& names);

// A rectangle placed for the whole display (centred text, the fixation cross) moved by the offset
// of the view's centre from the display's centre: where it goes in that eye's view.
PixelRect moved_into_view(const PixelRect& rect, const DisplaySpec& display, const EyeView& view);

// The view's pixels of a whole frame, and the way back (same size as the view), both refusing a
// view that does not lie inside the frame (std::invalid_argument). The view is cropped in colour
// only, without the frame's depth channel; the way back is core/pixel_rect.h's paste.
ImageRGBA crop_view(const ImageRGBA& frame, const PixelRect& viewport);
void paste_view(ImageRGBA& frame, const ImageRGBA& view_image, const PixelRect& viewport);

}  // namespace glarelab

#pragma once
// What a headset can show (docs/STEREO.md, "In a headset"): each eye sees its half of the frame
// through a view whose field of view the runtime gives (runner/display/openxr_clock.h,
// ViewFieldSource). The display model's degrees come from the views: a pixel of a half spans what
// its share of the view's field of view spans (headset_display_model), a pitch the file states must
// agree with them, and a scene wider or taller than a view's field of view cannot be shown at its
// size; each refused at its key (exit 2), after the display has opened and before the session's row
// is written.
#include <optional>
#include <string>

#include "protocols/experiment.h"
#include "runner/display/display_backend.h"
#include "runner/display/openxr_clock.h"
#include "stimuli/scene_library.h"

namespace glarelab {

// A pixel of a view's image (view_width_px x view_height_px, its swapchain image), seen at
// viewing_distance_mm: a projection layer maps the image's rectangle linearly onto the tangents of
// the view's edges (OpenXR 1.0, XrCompositionLayerProjectionView and XrFovf), as a flat screen at
// distance d spanning d (tan(right) - tan(left)) across and d (tan(up) - tan(down)) high does; its
// pixels are that span over the image's pixels each way (mm).
struct ViewPixelPitch {
  double across_mm = 0.0;
  double high_mm = 0.0;
};
ViewPixelPitch view_pixel_pitch(const ViewFieldOfView& view, int view_width_px, int view_height_px,
                                double viewing_distance_mm);

// The display model of a session on a display with views (OpenXR): each half of the frame is its
// view's image, so its pixel pitch at [display] viewing_distance_mm is the left eye's view's
// across (view_pixel_pitch); nothing for other displays.
struct HeadsetDisplayModel {
  double pixel_pitch_mm = 0.0;
  bool derived = false;    // the file left pixel_pitch_mm out: the session takes this one
  std::string description;  // the `display_model` event (docs/DATABASE.md)
};
// Throws ConfigError (exit 2) at [display] pixel_pitch_mm when the file states a pitch more than
// 1 % off the views' (naming theirs), and at height_px when a view's pixels would not be square
// within 1 % (naming the height that makes them so): the headset would stretch every scene.
std::optional<HeadsetDisplayModel> headset_display_model(const Experiment& experiment, const DisplayBackend& display);

// A headset shows each eye its half of a side-by-side frame (runner/display/openxr_display.h), and
// its mirror window is the keyboard's, not the participant's screen: with display "openxr", an
// experiment without stereo = "side_by_side", or with fullscreen, is refused (ConfigError, exit 2)
// at [display] output where the file chose the headset (`display_chosen` false), else at --display.
void check_headset_experiment(const Experiment& experiment, const std::string& display, bool display_chosen);

// Throws ConfigError at the scene's [scenes] key; nothing for a display without views of its own.
void check_scenes_fit_views(const Experiment& experiment, const SceneLibrary& scenes, const DisplayBackend& display);

}  // namespace glarelab

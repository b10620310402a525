#pragma once
// What a headset can show (docs/STEREO.md, "In a headset"): each eye sees its half of the frame
// through a view whose field of view the runtime gives (runner/display/openxr_clock.h,
// ViewFieldSource). A scene whose angular size by the display model ([display] pixel_pitch_mm at
// viewing_distance_mm) is wider or taller than a view's field of view cannot be seen at that size
// in the headset, whatever the frame's pixels: refused at the scene's key (exit 2), after the
// display has opened and before the session's row is written.
#include "protocols/experiment.h"
#include "runner/display/display_backend.h"
#include "stimuli/scene_library.h"

namespace glarelab {

// Throws ConfigError at the scene's [scenes] key; nothing for a display without views of its own.
void check_scenes_fit_views(const Experiment& experiment, const SceneLibrary& scenes, const DisplayBackend& display);

}  // namespace glarelab

#pragma once
// Each scene against the place the layout gives it (stimuli/layout.h; docs/EXPERIMENT_FILES.md,
// "Placement"), before the procedure is made and anything written: a scene that does not fit is
// refused, or scaled or cropped as its [scenes] entry's `fit` says, so nothing is cut silently.
#include "core/pixel_rect.h"
#include "protocols/experiment.h"
#include "stimuli/scene_library.h"

namespace glarelab {

// The place of every scene: the narrowest column (and the display's, or an eye's half's, height)
// when as many scenes stand side by side as the procedure's first trial shows (sequential forced
// choice: one), columns `stimulus_gap_deg` apart. Mono displays only; a stereo display's eye view is
// checked by check_stereo_layout (runner/session/session_eyes.h) unless the scene has a fit.
PixelRect scene_place(const Experiment& experiment, const SceneLibrary& scenes);

// Every scene larger than its place: with fit = "scale" resampled to the largest size of its aspect
// that fits (stimuli/scene_fit.h), with fit = "crop" cut about its centre. Without a fit, on a mono
// display, `refuse_misfits` (glarelab validate) makes it a ConfigError at the scene's [scenes] key
// naming the scene, its size and its place; otherwise (a run, whose files validate may not have
// seen) the scene is shown cropped by its column as the layout places it, and its note says so.
// A gap that leaves no column is a ConfigError at [display] stimulus_gap_deg.
void fit_scenes_to_places(const Experiment& experiment, SceneLibrary& scenes, bool refuse_misfits);

}  // namespace glarelab

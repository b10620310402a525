#pragma once
// The eyes of a stereo session ([display] stereo = "side_by_side"; stimuli/stereo_layout.h,
// docs/STEREO.md): each eye has its view (its half of the frame), its own glare stage (its own
// eye model, seeded per eye) and its own perception eye (its own adaptation), fed from its own
// samples of a binocular tracker. The session loop's per-eye work is in stereo_glare.cpp.
#include <cstdint>
#include <memory>
#include <vector>

#include "core/gl/gl_context.h"
#include "protocols/experiment.h"
#include "stimuli/glare_stage.h"
#include "stimuli/scene_library.h"
#include "stimuli/session_perception.h"
#include "stimuli/stereo_layout.h"

namespace glarelab {

struct StereoEye {
  StereoEye(const EyeView& eye_view, const Experiment& experiment, GlContextFactory gl_context);
  EyeView view;
  DisplaySpec display;  // the eye's view as a display of its own
  std::uint64_t seed = 0;
  GlareStage glare;
  SessionPerception perception;
};

// A stereo experiment's eyes, left first; none for a mono display.
std::vector<std::unique_ptr<StereoEye>> make_stereo_eyes(const Experiment& experiment, GlContextFactory gl_context);

// Before anything is written: in a stereo experiment every scene must fit its column in an eye's
// half of the display with as many scenes side by side as a trial shows (sequential forced choice:
// one), and no condition may look through traced spectacles (the lens is traced about the
// display's centre, not an eye's view). Throws ConfigError at [display] stereo.
void check_stereo_layout(const Experiment& experiment, const SceneLibrary& scenes);

}  // namespace glarelab

#pragma once
// The perception stages of Luidolt 2020 in the order of its Fig. 6.1, per frame and eye:
//   temporal adaptation (section 5.1) -> glare (section 5.2; supplied by the caller, or skipped)
//   -> acuity loss (5.3) -> tone mapping (6.1) -> scotopic colour (5.4).
// Adaptation is measured on the scene before glare ("in order to base the calculation solely on the
// scene luminances", 5.1); acuity works on linear cd/m2 before tone mapping; the scotopic shift
// comes after tone mapping and reads the adapted luminance from before it (5.4, 6.5).
// Every stage can be switched off. With adaptation off the eye adapts instantly: the adapted
// luminance is the frame's own adaptation luminance and the eye's state is left as it was.
// `PerceptionSettings` (core/perception_settings.h) is the shape the experiment file's [perception]
// table maps onto (protocols/perception_config.h).
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/display_spec.h"
#include "core/image.h"
#include "core/perception_settings.h"
#include "stimuli/perception/acuity_loss.h"
#include "stimuli/perception/frame_adaptation_luminance.h"
#include "stimuli/perception/scotopic_colour.h"
#include "stimuli/perception/temporal_adaptation.h"
#include "stimuli/perception/tone_mapping.h"

namespace glarelab {

enum class PerceptionStage { adaptation, glare, acuity, tone_mapping, scotopic };
const char* perception_stage_name(PerceptionStage stage);

// Throws std::invalid_argument naming the field (e.g. "acuity.max_sigma_px") and its accepted range.
void validate_perception_settings(const PerceptionSettings& settings);
// validate_perception_settings, and the eye made from the same adaptation time constants (throws
// std::invalid_argument otherwise): what both runs of the stages (CPU, GL) check first.
void check_perception_inputs(const TemporalAdaptation& eye, const PerceptionSettings& settings);

// Glare on the adapted scene (cd/m2 in, cd/m2 out), e.g. stimuli/glare_stage.h's; empty: skipped.
using PerceptionGlare = std::function<ImageRGBA(const ImageRGBA&)>;

struct PerceptionFrameInput {
  double gaze_x = 0.5, gaze_y = 0.5;  // normalised display coordinates (0..1, top left, y down)
  double frame_time_s = 0.0;          // how long this frame is shown (Eq. 5.2's ft)
};

struct PerceptionResult {
  ImageRGBA image;                          // display cd/m2 after tone mapping, else scene cd/m2
  double frame_luminance_cd_m2 = 0.0;       // this frame's adaptation luminance (5.1)
  double adapted_luminance_cd_m2 = 0.0;     // L_i (Eq. 5.2), what tone mapping and scotopic used
  std::vector<PerceptionStage> stages_run;  // in the order they ran
  // The GL stages: each stage's time on the GPU's clock (GL_TIMESTAMP queries between them, in the
  // order they ran: "adaptation", "glare", "acuity", "tone mapping", "scotopic", "kept"), seconds;
  // empty on the CPU.
  std::vector<std::pair<std::string, double>> gpu_stages_s;
};

// Runs the enabled stages on one frame of scene luminances (linear Rec.709, cd/m2) and advances
// `eye` (when adaptation is on) by frame_time_s.
PerceptionResult run_perception_stages(const ImageRGBA& scene, const PerceptionFrameInput& input,
                                       TemporalAdaptation& eye, const PerceptionSettings& settings,
                                       const DisplaySpec& display, const PerceptionGlare& glare = {});

}  // namespace glarelab

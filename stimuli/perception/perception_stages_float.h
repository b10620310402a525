#pragma once
// The perception stages of perception_stages.h on float32 frames, in place, each split over row
// chunks (core/parallel_for.h): what the CPU frame engine runs in sessions (stimuli/frame_engine.h).
// The float64 functions of each stage stay the reference (tests/perception_float_test.cpp: each
// stage within 1e-5 relative by stage_timing.h's pixel metric, on a frame with a 1e6 cd/m2 lamp
// beside 0.01 cd/m2, zeros and one-pixel edges); `glarelab bench` prints each beside its streaming
// floor (core/streaming_floor.h).
//   adaptation:   frame_adaptation_luminance_float_cd_m2 (frame_adaptation_luminance.h)
//   acuity:       apply_acuity_loss_float (acuity_loss_float.h)
//   tone mapping: the curves of tone_mapping.h per pixel in float; the exposure per frame in double;
//                 Narkowicz's input is held at 16, where the clamped curve is 1 already (it reaches
//                 1 at x = 7.24), so a 1e6 cd/m2 lamp cannot overflow its square
//   scotopic:     Eq. 5.18 or Spencer's desaturation per pixel in float, the rod sensitivity in double
// Each result does not depend on the thread count. The adapted luminance, the eye and the rod
// sensitivity are the float64 ones of perception_stages.cpp.
#include "core/image.h"
#include "stimuli/perception/perception_stages.h"

namespace glarelab {

// One per hardware thread (core/parallel_for.h, resolved_threads(0)).
int perception_float_threads();

// tone_map and apply_scotopic_colour on `frame`, in place (alpha kept); the same checks and messages.
void tone_map_float(ImageRGBA& frame, double adapted_luminance_cd_m2, const ToneMappingSettings& settings,
                    double peak_luminance_cd_m2, int threads);
void apply_scotopic_colour_float(ImageRGBA& frame, double rod_sensitivity, const ScotopicSettings& settings, int threads);

// run_perception_stages on the float32 stages: the same switches, order, eye and result.
PerceptionResult run_perception_stages_float(const ImageRGBA& scene, const PerceptionFrameInput& input,
                                             TemporalAdaptation& eye, const PerceptionSettings& settings,
                                             const DisplaySpec& display, const PerceptionGlare& glare = {},
                                             int threads = perception_float_threads());

}  // namespace glarelab

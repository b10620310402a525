#pragma once
// The perception stages of Luidolt 2020 in the order of its Fig. 6.1 on the GPU, the GL counterpart
// of perception_stages.h's run_perception_stages, with the same switches, settings, validation and
// result: adaptation luminance (GlFrameAdaptationLuminance) -> the temporal filter (Eqs. 5.2-5.4,
// a scalar, on the CPU: TemporalAdaptation) -> glare (the caller's, on the CPU: the frame is read
// back and uploaded again around it) -> acuity loss (GlAcuityLoss) -> tone mapping (GlToneMapping)
// -> scotopic colour (GlScotopicColour). One upload, one read-back per frame (two more with glare).
// Requires a current OpenGL 4.5 context; not thread-safe.
#include <memory>

#include "stimuli/perception/gl_acuity_loss.h"
#include "stimuli/perception/gl_frame_adaptation_luminance.h"
#include "stimuli/perception/gl_frame_buffer.h"
#include "stimuli/perception/gl_scotopic_colour.h"
#include "stimuli/perception/gl_tone_mapping.h"
#include "stimuli/perception/perception_stages.h"

namespace glarelab::gl {

class GlPerceptionStages {
 public:
  GlPerceptionStages() = default;

  // As run_perception_stages: throws std::invalid_argument naming the settings group and field,
  // or when `eye` was made with other time constants; advances `eye` when adaptation is on.
  PerceptionResult run(const ImageRGBA& scene, const PerceptionFrameInput& input, TemporalAdaptation& eye,
                       const PerceptionSettings& settings, const DisplaySpec& display,
                       const PerceptionGlare& glare = {});

 private:
  GlFrameAdaptationLuminance adaptation_;
  GlAcuityLoss acuity_;
  GlToneMapping tone_mapping_;
  GlScotopicColour scotopic_;
  std::unique_ptr<GlFrameBuffer> frame_, blurred_;  // kept while the frame size stays the same
};

}  // namespace glarelab::gl

#pragma once
// The perception stages of Luidolt 2020 over a session's frames (Fig. 6.1: adaptation -> glare ->
// acuity -> tone mapping -> scotopic colour; stimuli/perception/perception_stages.h). One eye
// adapts over the whole session (Eqs. 5.2-5.4, exact for any frame time): it starts adapted to
// the display's background, what the participant saw before the first stimulus frame (fixation,
// screens and intervals are drawn on it), each processed frame advances it by the time the frame
// is shown, the frames shown without stages advance it by their measured adaptation luminance
// (see()), and the time between (screens, fixation, inter-trial intervals) it is taken to see the
// display's background. The glare between adaptation and acuity is the caller's (stimuli/glare_stage.h),
// handed the adapted luminance as its field luminance when adaptation is on, so the eye whose
// pupil spreads the glare is the eye the image is tone mapped for.
#include <functional>
#include <optional>

#include "core/display_spec.h"
#include "core/image.h"
#include "core/perception_settings.h"
#include "stimuli/perception/perception_stages.h"
#include "stimuli/perception/temporal_adaptation.h"

namespace glarelab {

// Glare on the adapted scene (cd/m2 in and out) with the field luminance the eye adapts to
// (cd/m2): the adapted luminance when adaptation is on, nothing otherwise (the glare stage then
// takes the frame's mean luminance, as without perception stages).
using FieldGlare = std::function<ImageRGBA(const ImageRGBA&, std::optional<double> field_luminance_cd_m2)>;

// What runs the stages of one frame: run_perception_stages_float (the CPU's) or an engine's
// (stimuli/frame_engine.h), with its arguments and result.
using PerceptionStagesRun =
    std::function<PerceptionResult(const ImageRGBA& scene, const PerceptionFrameInput& input, TemporalAdaptation& eye,
                                   const PerceptionSettings& settings, const DisplaySpec& display,
                                   const PerceptionGlare& glare)>;

class SessionPerception {
 public:
  // `time_constants` are the experiment's (every condition shares the one eye).
  SessionPerception(const AdaptationTimeConstants& time_constants, const DisplaySpec& display);

  // A frame of the session shown from flip_s for frame_time_s through the stages `settings`
  // switches on; `gaze` in normalised display coordinates (the display centre without a tracker).
  // `glare` may be empty (a control condition); `stages` runs them (empty: on the CPU,
  // stimuli/perception/perception_stages_float.h). The eye is advanced whether or not adaptation is
  // on: with adaptation off the frame is tone mapped for its own adaptation luminance (the eye
  // adapting instantly), but the session's eye still saw it.
  PerceptionResult process(const ImageRGBA& composed_cd_m2, const PerceptionSettings& settings, double flip_s,
                           double frame_time_s, double gaze_x, double gaze_y, const FieldGlare& glare = {},
                           const PerceptionStagesRun& stages = {});

  // Frames from_frame .. to_frame - 1 of an interval, frame k flipping at first_flip_s + k
  // frame_time_s, shown without stages (or not computed: a preview passing by), all of adaptation
  // luminance frame_luminance_cd_m2 (section 5.1): the eye sees each for its frame time, in the
  // same steps as process() would take, so a preview's eye is the session's to the last bit (Eq.
  // 5.2 makes one step over the whole stretch equal to these up to rounding).
  void see(double frame_luminance_cd_m2, double first_flip_s, double frame_time_s, int from_frame, int to_frame);

  // The eye's adapted luminance now (cd/m2), nothing before the first frame.
  std::optional<double> adapted_luminance_cd_m2() const;

 private:
  // The eye brought to flip_s over the background shown since the last frame it saw; made,
  // adapted to `first_luminance_cd_m2` (the display's background), at the first frame.
  TemporalAdaptation& eye_at(double flip_s, double first_luminance_cd_m2);

  AdaptationTimeConstants time_constants_;
  DisplaySpec display_;
  std::optional<TemporalAdaptation> eye_;
  double seen_until_s_ = 0.0;
};

}  // namespace glarelab

#include "stimuli/session_perception.h"

#include <algorithm>

#include "stimuli/perception/perception_stages_float.h"

namespace glarelab {

SessionPerception::SessionPerception(const AdaptationTimeConstants& time_constants, const DisplaySpec& display)
    : time_constants_(time_constants), display_(display) {}

TemporalAdaptation& SessionPerception::eye_at(double flip_s, double first_luminance_cd_m2) {
  if (!eye_) {
    eye_.emplace(first_luminance_cd_m2, time_constants_);
    seen_until_s_ = flip_s;
  }
  // Between the frames it saw, the display showed its background (a uniform field adapts to its
  // own luminance exactly, section 5.1's weighted mean).
  if (flip_s > seen_until_s_) eye_->advance(display_.background_cd_m2, flip_s - seen_until_s_);
  return *eye_;
}

PerceptionResult SessionPerception::process(const ImageRGBA& composed_cd_m2, const PerceptionSettings& settings,
                                            double flip_s, double frame_time_s, double gaze_x, double gaze_y,
                                            const FieldGlare& glare, const PerceptionStagesRun& stages) {
  // Before the session's first stimulus frame the participant saw the display's background (the
  // fixation, the inter-trial interval and any screen are drawn on it): the eye meets that frame
  // adapted to the background, a uniform field adapting to its own luminance (Luidolt 2020 5.1),
  // and adapts to the frame from there (Eq. 5.2). After that the stages measure each frame.
  TemporalAdaptation& eye = eye_at(flip_s, display_.background_cd_m2);
  PerceptionGlare stage_glare;
  if (glare) {
    // run_perception_stages advances the eye before the glare (Fig. 6.1), so the eye's luminance
    // here is this frame's L_i (Eq. 5.2).
    stage_glare = [&](const ImageRGBA& adapted_scene) {
      return glare(adapted_scene, settings.adaptation ? std::optional<double>(eye.adapted_luminance_cd_m2())
                                                      : std::nullopt);
    };
  }
  PerceptionFrameInput input;
  input.gaze_x = gaze_x;
  input.gaze_y = gaze_y;
  input.frame_time_s = frame_time_s;
  PerceptionResult result = stages ? stages(composed_cd_m2, input, eye, settings, display_, stage_glare)
                                   : run_perception_stages_float(composed_cd_m2, input, eye, settings, display_, stage_glare);
  if (!settings.adaptation) eye.advance(result.frame_luminance_cd_m2, frame_time_s);
  seen_until_s_ = std::max(seen_until_s_, flip_s + frame_time_s);
  return result;
}

void SessionPerception::see(double frame_luminance_cd_m2, double first_flip_s, double frame_time_s, int from_frame,
                            int to_frame) {
  for (int k = from_frame; k < to_frame; ++k) {
    const double flip_s = first_flip_s + k * frame_time_s;
    eye_at(flip_s, display_.background_cd_m2).advance(frame_luminance_cd_m2, frame_time_s);
    seen_until_s_ = std::max(seen_until_s_, flip_s + frame_time_s);
  }
}

std::optional<double> SessionPerception::adapted_luminance_cd_m2() const {
  if (!eye_) return std::nullopt;
  return eye_->adapted_luminance_cd_m2();
}

}  // namespace glarelab

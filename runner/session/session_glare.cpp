// A session's glare made (each eye's frame engine), its setup logged, and what the session loop
// asks of an interval besides its frames: how they are presented and, after the timed sequence,
// their reports.
#include "runner/session/session_glare.h"

#include <cmath>

#include "core/number_text.h"
#include "runner/display/compute_context.h"

namespace glarelab {

SessionGlare::SessionGlare(const PreparedSession& prepared, FrameRenderer& renderer, DisplayBackend& display,
                           SessionClock& clock, ResultStore& store, std::int64_t session_id, TrackerSession& tracker,
                           PreviewCapture& capture)
    : prepared_(prepared),
      renderer_(renderer),
      display_(display),
      clock_(clock),
      store_(store),
      session_id_(session_id),
      tracker_(tracker),
      capture_(capture),
      period_s_(1.0 / display.refresh_hz()),
      // The display's own context: the GL engine's frames stay on the GPU where the display draws
      // them (stimuli/frame_engine.h).
      eyes_(make_session_eyes(prepared.experiment, display.width_px(), display.height_px(),
                              gl::display_context_factory(display))) {
  for (const ConditionRefraction& refraction : condition_refractions(prepared_.experiment))
    condition_refractions_.emplace(refraction.condition, refraction);
  log_glare_setup();
  log_stereo_setup();
  for (const ConditionRow& row : prepared_.experiment.conditions)
    adapts_ = adapts_ || perception_for(prepared_.experiment.perception, row).adaptation;
}

bool SessionGlare::prepared_before_onset(const IntervalGlare& glare) const {
  return presentation_for(glare) == GlarePresentation::prepared;
}

bool SessionGlare::shown_live(const IntervalGlare& glare) const {
  return glare.computed() && presentation_for(glare) == GlarePresentation::live;
}

void SessionGlare::report_interval(const TrialPlan& plan, const IntervalGlare& glare) {
  log_interval_glare(plan, glare);
  settle_glare_presentation(plan, glare);
  review_live_presentation(plan, glare);
  log_perception_stages(plan, glare);
  log_stereo_eyes(plan, glare);
  log_read_backs(plan, glare);
}

void SessionGlare::log_read_backs(const TrialPlan& plan, const IntervalGlare& glare) {
  if (!glare.computed() || !glare.read_backs_after_first_from) return;
  bool on_gl = false;
  for (const std::unique_ptr<SessionEye>& eye : eyes_) on_gl = on_gl || eye->engine.kind() == FrameEngineKind::gl;
  if (!on_gl) return;
  const gl::ReadBackTally after = gl::read_back_tally().since(*glare.read_backs_after_first_from);
  log_trial_event(clock_.now_s(), "read_backs",
                  "trial " + std::to_string(plan.trial_index) + " (" + glare.modes_label + ", " +
                      std::to_string(glare.frames.size()) + " frame(s) computed for " +
                      std::to_string(glare.stimulus_frames) + " stimulus frame(s)): frame 0 read back " +
                      glare.read_backs_first_frame.describe() + "; after frame 0: " + after.describe());
  if (glare.gpu_stage_sums.empty()) return;
  std::string times;
  for (const IntervalGlare::GpuStageSum& sum : glare.gpu_stage_sums)
    times += (times.empty() ? "" : ", ") + sum.stage + " " +
             number_text(std::round(1e6 * sum.seconds / sum.frames) / 1e3) + " ms";
  log_trial_event(clock_.now_s(), "gpu_stage_times",
                  "trial " + std::to_string(plan.trial_index) + " (" + glare.modes_label +
                      "): GPU time per frame (timer queries, mean over " +
                      std::to_string(glare.gpu_stage_sums.front().frames) + " frame(s)): " + times);
}

}  // namespace glarelab

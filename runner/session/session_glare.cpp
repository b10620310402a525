// A session's glare made (each eye's frame engine), its setup logged, and what the session loop
// asks of an interval besides its frames: how they are presented and, after the timed sequence,
// their reports.
#include "runner/session/session_glare.h"

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
      eyes_(make_session_eyes(prepared.experiment, display.width_px(), display.height_px(),
                              gl::compute_context_factory())) {
  for (const ConditionRefraction& refraction : condition_refractions(prepared_.experiment))
    condition_refractions_.emplace(refraction.condition, refraction);
  log_glare_setup();
  log_stereo_setup();
  for (const ConditionRow& row : prepared_.experiment.conditions)
    adapts_ = adapts_ || perception_for(prepared_.experiment.perception, row).adaptation;
}

bool SessionGlare::prepared_before_onset(const IntervalGlare& glare) const {
  // Perception stages are prepared before onset whatever the glare's presentation: the session's
  // eye then sees its frames in the order they flip.
  return presentation_for(glare) == GlarePresentation::prepared || glare.perceived();
}

bool SessionGlare::shown_live(const IntervalGlare& glare) const {
  return glare.made == IntervalFrames::glare && presentation_for(glare) == GlarePresentation::live;
}

void SessionGlare::report_interval(const TrialPlan& plan, const IntervalGlare& glare) {
  log_interval_glare(plan, glare);
  settle_glare_presentation(plan, glare);
  review_live_presentation(plan, glare);
  log_perception_stages(plan, glare);
  log_stereo_eyes(plan, glare);
}

}  // namespace glarelab

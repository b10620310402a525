// A trial whose stimulus is a physical object (core/real_stimulus.h, scene "real:desk lamp";
// Luidolt 2020, 7.2: the real desk lamp before its simulation): nothing is rendered. The interval
// is the display's background with the instruction to look at the object, centred, where an
// image would be; the question goes above it, and both stay up until the answer.
#include "core/real_stimulus.h"
#include "runner/session/session_loop.h"

namespace glarelab {

IntervalGlare SessionLoop::begin_real_stimulus(const TrialPlan& plan, int flips_before) {
  // Inactive: no glare and no perception stage, the drawn frame is shown as it is. The session's
  // model eye is not shown these frames (the observer looks away from the display, at the
  // object): it takes the time as background, as it does for screens and fixation.
  IntervalGlare interval;
  interval.period_s = period_s_;
  interval.first_flip_s = clock_.now_s() + (1 + flips_before) * period_s_;
  interval.stimulus_frames = plan.stimulus_frames;
  interval.modes_label = "real stimulus '" + plan.real_stimulus + "'";
  if (capture_.captures(plan) && !capture_.frame) {
    capture_.frame.emplace();
    capture_.frame->plan = plan;
    capture_.frame->time_s = interval.first_flip_s;
    capture_.frame->glare_label = interval.modes_label;
  }
  return interval;
}

std::vector<Placement> SessionLoop::real_stimulus_instruction_overlay(const TrialPlan& plan) {
  if (plan.real_stimulus.empty()) return {};
  return overlays_.centred_text(real_stimulus_instruction(plan.real_stimulus));
}

}  // namespace glarelab

// The response phase of a double-adjustment trial: both comparison spots on screen, stepped by
// keys, wheel clicks or device buttons (runner/session/adjustment_keys.h) until the setting is
// accepted; every flip of it is recorded with the trial.
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "protocols/adjustment_procedure.h"
#include "runner/session/adjustment_keys.h"
#include "runner/session/session_loop.h"

namespace glarelab {

std::optional<Response> SessionLoop::adjust_interactively(const TrialPlan& plan, TrialRun& run) {
  const double onset_s = run.onset_s;
  TrialPlan shown = plan;
  AdjustmentControl control(prepared_.experiment.adjustment);
  double offset_log10 = 0.0;
  const auto setting = [&](std::size_t spot) { return plan.adjustment_start_cd_m2[spot] * std::pow(10.0, offset_log10); };
  const double comparison_peak_cd_m2 = plan.adjustment_start_cd_m2[0] / plan.scene_scale[0];
  while (true) {
    shown.scene_scale = {setting(0) / comparison_peak_cd_m2, 1.0, setting(1) / comparison_peak_cd_m2};
    draw(layout(shown));
    const double flip_s = present();
    timing_.on_flip(flip_s, plan.trial_index, -1);
    after_flip(flip_s);
    record_flip(run, {FlipPhase::response, -1, -1}, flip_s, flip_s, false);
    check_interrupt();
    if (!aborted_ && display_.close_requested()) {
      aborted_ = true;
      abort_reason_ = display_.close_reason();
    }
    if (aborted_) return std::nullopt;
    for (const TimedInput& input : adjustment_inputs(plan, onset_s)) {
      if (input.name == "escape" && input.source == TimedInput::Source::key) {
        aborted_ = true;
        abort_reason_ = "Escape pressed";
        return std::nullopt;
      }
      const AdjustmentStep step = control.apply(input.name, input.shift);
      if (step.effect == AdjustmentEffect::accept)
        return Response{format_adjustment_response(setting(0), setting(1)), input.session_time_s - onset_s};
      if (step.effect == AdjustmentEffect::step) offset_log10 += step.log10_step;
      if (step.effect == AdjustmentEffect::mode_change)
        store_.log_event(session_id_, input.session_time_s, "adjustment_mode",
                         "trial " + std::to_string(plan.trial_index) + ": fine mode " + (control.fine_mode() ? "on" : "off"));
      if (step.effect == AdjustmentEffect::none && device_ != nullptr) device_->log_not_adjusting(plan, input);
      if (step.effect == AdjustmentEffect::none && device_ == nullptr)
        store_.log_event(session_id_, input.session_time_s, "ignored_key",
                         "trial " + std::to_string(plan.trial_index) + ": key '" + input.name + "' does not adjust");
    }
    if (aborted_) return std::nullopt;  // the device pause ended the trial
  }
}

std::vector<TimedInput> SessionLoop::adjustment_inputs(const TrialPlan& plan, double onset_s) {
  std::vector<TimedInput> inputs;
  if (device_ != nullptr) {
    bool unplugged = false;
    inputs = device_->adjustment_presses(plan, onset_s, &unplugged);
    if (unplugged && inputs.empty()) {
      pause_for_response_device(plan.trial_index);
      return {};
    }
  }
  for (const InputEvent& event : display_.poll_input())
    inputs.push_back({event.is_key() ? TimedInput::Source::key : TimedInput::Source::wheel, event.name, event.shift,
                      clock_.now_s()});
  return inputs;
}

}  // namespace glarelab

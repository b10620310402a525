#include "runner/session/adjustment_keys.h"

#include <cmath>
#include <sstream>

namespace glarelab {

AdjustmentStep AdjustmentControl::apply(const std::string& input, bool shift) {
  const double coarse = spec_.coarse_step_log10;
  const double fine = spec_.fine_step_log10;
  const double moded = (fine_mode_ || shift) ? fine : coarse;
  const auto step = [](double log10_step) { return AdjustmentStep{AdjustmentEffect::step, log10_step}; };
  if (input == "up" || input == "wheel_up") return step(moded);
  if (input == "down" || input == "wheel_down") return step(-moded);
  if (input == "coarse_up") return step(coarse);
  if (input == "coarse_down") return step(-coarse);
  if (input == "right" || input == "fine_up") return step(fine);
  if (input == "left" || input == "fine_down") return step(-fine);
  if (accepts_adjustment(input)) return {AdjustmentEffect::accept, 0.0};
  if (input == "f" || input == "fine_mode") {
    fine_mode_ = !fine_mode_;
    return {AdjustmentEffect::mode_change, 0.0};
  }
  return {};
}

std::optional<double> adjustment_factor(const std::string& input, const AdjustmentSpec& spec) {
  AdjustmentControl control(spec);
  const AdjustmentStep step = control.apply(input, false);
  if (step.effect != AdjustmentEffect::step) return std::nullopt;
  return std::pow(10.0, step.log10_step);
}

bool accepts_adjustment(const std::string& input) { return input == "enter" || input == "space" || input == "accept"; }

std::string describe_adjustment_keys(const AdjustmentSpec& spec) {
  std::ostringstream text;
  text << "up/down or the mouse wheel: both spots x or / 10^" << spec.coarse_step_log10 << " (10^"
       << spec.fine_step_log10 << " with Shift held or in fine mode, F switches it), right/left: x or / 10^"
       << spec.fine_step_log10 << ", Enter or Space accepts; Escape ends the session";
  return text.str();
}

}  // namespace glarelab

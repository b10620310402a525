#include "runner/session/adjustment_keys.h"

#include <cmath>
#include <sstream>

namespace glarelab {

std::optional<double> adjustment_factor(const std::string& key, const AdjustmentSpec& spec) {
  if (key == "up") return std::pow(10.0, spec.coarse_step_log10);
  if (key == "down") return std::pow(10.0, -spec.coarse_step_log10);
  if (key == "right") return std::pow(10.0, spec.fine_step_log10);
  if (key == "left") return std::pow(10.0, -spec.fine_step_log10);
  return std::nullopt;
}

bool accepts_adjustment(const std::string& key) { return key == "enter" || key == "space"; }

std::string describe_adjustment_keys(const AdjustmentSpec& spec) {
  std::ostringstream text;
  text << "up/down: both spots x or / 10^" << spec.coarse_step_log10 << ", right/left: x or / 10^" << spec.fine_step_log10
       << ", Enter or Space accepts; Escape ends the session";
  return text.str();
}

}  // namespace glarelab

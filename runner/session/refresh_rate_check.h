#pragma once
// Durations are counted in frames of the experiment's [display] refresh_hz; a display running at
// another rate shows every duration scaled by the ratio. A difference above 1 % is warned about.
#include <string>

namespace glarelab {

// Relative difference above which the rates are said to differ.
inline constexpr double kRefreshRateTolerance = 0.01;

// Empty when |actual - experiment| <= 1 % of the experiment's rate; otherwise a sentence naming
// both rates and what it does to the durations.
std::string refresh_rate_warning(double experiment_refresh_hz, double display_refresh_hz);

}  // namespace glarelab

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

// Relative departure of the measured flip interval from the nominal refresh period above which
// the flips are said not to follow the refresh.
inline constexpr double kFlipIntervalTolerance = 0.10;

// Empty when the measured flip interval (timing-test: the mean; a session: the median, which a
// few long pauses between trials do not move) is within 10 % of 1 / refresh_hz; otherwise a
// sentence with both intervals and the likely cause: shorter, the buffer swap does not wait for
// the vertical blank (vsync off, a virtual display such as Xvfb); about n periods for a whole
// n >= 2, a compositor or a display running at refresh_hz / n; otherwise another refresh rate.
std::string flip_interval_warning(double refresh_hz, double measured_interval_s);

}  // namespace glarelab

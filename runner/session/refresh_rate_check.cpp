#include "runner/session/refresh_rate_check.h"

#include <cmath>
#include <sstream>

namespace glarelab {

std::string refresh_rate_warning(double experiment_refresh_hz, double display_refresh_hz) {
  const double difference = std::abs(display_refresh_hz - experiment_refresh_hz);
  if (difference <= kRefreshRateTolerance * experiment_refresh_hz) return "";
  std::ostringstream text;
  text << "the display refreshes at " << display_refresh_hz << " Hz, not the experiment's refresh_hz "
       << experiment_refresh_hz << " Hz ([display]): durations counted in frames last "
       << experiment_refresh_hz / display_refresh_hz << " times as long as planned";
  return text.str();
}

std::string flip_interval_warning(double refresh_hz, double measured_interval_s) {
  const double nominal_s = 1.0 / refresh_hz;
  const double ratio = measured_interval_s / nominal_s;
  if (!(measured_interval_s > 0.0) || std::abs(ratio - 1.0) <= kFlipIntervalTolerance) return "";
  std::ostringstream text;
  text.precision(4);
  text << "the flips come every " << 1000.0 * measured_interval_s << " ms, not every " << 1000.0 * nominal_s
       << " ms (" << refresh_hz << " Hz): ";
  const double whole = std::round(ratio);
  if (ratio < 1.0) {
    text << "the buffer swap does not wait for the vertical blank (vsync off in the driver or its settings, or a "
            "virtual display such as Xvfb that has none), so frames are shown for less than a refresh and "
            "durations counted in frames are shorter than planned";
  } else if (whole >= 2.0 && std::abs(ratio - whole) <= kFlipIntervalTolerance * whole) {
    text << "each frame stays " << whole << " refreshes: a compositor adding a frame of latency, or a display "
         << "running at " << refresh_hz / whole << " Hz; durations counted in frames last " << whole
         << " times as long as planned";
  } else {
    text << "the display seems to refresh at " << 1.0 / measured_interval_s
         << " Hz: set its mode to the experiment's rate, or [display] refresh_hz to its own";
  }
  return text.str();
}

}  // namespace glarelab

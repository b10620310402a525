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

}  // namespace glarelab

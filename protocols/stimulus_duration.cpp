#include "protocols/stimulus_duration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace glarelab {

int duration_to_frames(double duration_s, double refresh_hz) {
  const double period_s = 1.0 / refresh_hz;
  // A relative tolerance keeps 1/60 s written as 0.016667 from counting as shorter than a frame.
  if (duration_s < period_s * (1.0 - 1e-3)) {
    throw std::invalid_argument("shorter than one frame (" + std::to_string(1000.0 * period_s) + " ms at " +
                                std::to_string(refresh_hz) + " Hz)");
  }
  const double frames = std::round(duration_s * refresh_hz);
  if (frames > std::numeric_limits<int>::max()) throw std::invalid_argument("too long");
  return std::max(1, static_cast<int>(frames));
}

void read_stimulus_duration(TableReader& procedure, double refresh_hz, ForcedChoiceSpec& spec) {
  const std::optional<std::int64_t> frames = procedure.integer("stimulus_frames");
  const std::optional<double> seconds = procedure.number("stimulus_duration_s");
  if (frames && seconds)
    procedure.fail_at_key("stimulus_duration_s", "give either stimulus_frames or stimulus_duration_s, not both");
  if (frames) {
    if (*frames < 1 || *frames > std::numeric_limits<int>::max())
      procedure.fail("stimulus_frames", "must be >= 1, found " + std::to_string(*frames));
    spec.stimulus_frames = static_cast<int>(*frames);
    spec.stimulus_duration_s.reset();
  } else if (seconds) {
    try {
      spec.stimulus_frames = duration_to_frames(*seconds, refresh_hz);
    } catch (const std::invalid_argument& error) {
      procedure.fail("stimulus_duration_s", std::to_string(*seconds) + " s is " + error.what());
    }
    spec.stimulus_duration_s = *seconds;
  }
}

std::string describe_duration_rounding(const ForcedChoiceSpec& spec, double refresh_hz) {
  if (!spec.stimulus_duration_s) return "";
  const double shown_s = spec.stimulus_frames / refresh_hz;
  std::ostringstream text;
  text << "stimulus_duration_s " << *spec.stimulus_duration_s << " s -> " << spec.stimulus_frames << " frames = "
       << shown_s << " s at " << refresh_hz << " Hz (rounding " << 1000.0 * (shown_s - *spec.stimulus_duration_s)
       << " ms)";
  return text.str();
}

}  // namespace glarelab

#include "protocols/stimulus_duration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/number_text.h"

namespace glarelab {

int duration_to_frames(double duration_s, double refresh_hz) {
  const double period_s = 1.0 / refresh_hz;
  // A relative tolerance keeps 1/60 s written as 0.016667 from counting as shorter than a frame.
  if (duration_s < period_s * (1.0 - 1e-3)) {
    throw std::invalid_argument("shorter than one frame (" + number_text(1000.0 * period_s) + " ms at " +
                                number_text(refresh_hz) + " Hz)");
  }
  const double frames = std::round(duration_s * refresh_hz);
  if (frames > std::numeric_limits<int>::max()) throw std::invalid_argument("too long");
  return std::max(1, static_cast<int>(frames));
}

FrameCount read_frame_count(TableReader& reader, std::string_view frames_key, std::string_view seconds_key,
                            double refresh_hz, FrameCount fallback, bool zero_allowed) {
  const std::optional<std::int64_t> frames = reader.integer(frames_key);
  const std::optional<double> seconds = reader.number(seconds_key);
  if (frames && seconds)
    reader.fail_at_key(seconds_key, "give either " + std::string(frames_key) + " or " + std::string(seconds_key) +
                                        ", not both");
  const std::int64_t minimum = zero_allowed ? 0 : 1;
  if (frames) {
    if (*frames < minimum || *frames > std::numeric_limits<int>::max())
      reader.fail(frames_key, "must be >= " + number_text(minimum) + ", found " + number_text(*frames));
    return FrameCount{static_cast<int>(*frames), std::nullopt};
  }
  if (seconds) {
    if (zero_allowed && *seconds == 0.0) return FrameCount{0, 0.0};
    if (*seconds < 0.0) reader.fail(seconds_key, "must be >= 0, found " + number_text(*seconds));
    try {
      return FrameCount{duration_to_frames(*seconds, refresh_hz), *seconds};
    } catch (const std::invalid_argument& error) {
      reader.fail(seconds_key, number_text(*seconds) + " s is " + error.what());
    }
  }
  return fallback;
}

std::string describe_rounding(std::string_view seconds_key, const FrameCount& count, double refresh_hz) {
  if (!count.seconds) return "";
  const double shown_s = count.frames / refresh_hz;
  std::ostringstream text;
  text << seconds_key << " " << *count.seconds << " s -> " << count.frames << " frames = " << shown_s << " s at "
       << refresh_hz << " Hz (rounding " << 1000.0 * (shown_s - *count.seconds) << " ms)";
  return text.str();
}

void read_stimulus_duration(TableReader& procedure, double refresh_hz, ForcedChoiceSpec& spec) {
  const FrameCount count = read_frame_count(procedure, "stimulus_frames", "stimulus_duration_s", refresh_hz,
                                            FrameCount{spec.stimulus_frames, spec.stimulus_duration_s}, false);
  spec.stimulus_frames = count.frames;
  spec.stimulus_duration_s = count.seconds;
}

std::string describe_duration_rounding(const ForcedChoiceSpec& spec, double refresh_hz) {
  return describe_rounding("stimulus_duration_s", FrameCount{spec.stimulus_frames, spec.stimulus_duration_s}, refresh_hz);
}

}  // namespace glarelab

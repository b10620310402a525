#pragma once
// The session clock of a display whose flips are predicted, not observed (OpenXR): now_s() is the
// monotonic clock's, and on_flip() returns the time the runtime predicted the frame just submitted
// will be shown (XrFrameState::predictedDisplayTime, converted to CLOCK_MONOTONIC, which is
// steady_clock on Linux). OpenXR reports no presentation time; docs/TIMING.md says how onsets in a
// headset are checked.
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "core/clock.h"

namespace glarelab {

// A display that predicts when the frame it last presented is shown (the OpenXR display), rather
// than presenting it when present() returns.
class PredictedFlipSource {
 public:
  virtual ~PredictedFlipSource() = default;
  // nullopt before the first frame was submitted.
  virtual std::optional<std::chrono::steady_clock::time_point> predicted_display_time() const = 0;
};

class PredictedFlipClock final : public SessionClock {
 public:
  // start_offset_s lets a resumed session continue its time line after the last logged flip.
  PredictedFlipClock(const PredictedFlipSource& display, double start_offset_s = 0.0);
  double now_s() const override;
  // Throws std::logic_error when the display has predicted no flip yet.
  double on_flip() override;
  std::string name() const override { return "predicted"; }

 private:
  const PredictedFlipSource& display_;
  std::chrono::steady_clock::time_point start_;
  double start_offset_s_;
};

}  // namespace glarelab

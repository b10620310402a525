#include "runner/display/openxr_clock.h"

#include <stdexcept>

namespace glarelab {

PredictedFlipClock::PredictedFlipClock(const PredictedFlipSource& display, double start_offset_s)
    : display_(display), start_(std::chrono::steady_clock::now()), start_offset_s_(start_offset_s) {}

double PredictedFlipClock::now_s() const {
  return start_offset_s_ + std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

double PredictedFlipClock::on_flip() {
  const std::optional<std::chrono::steady_clock::time_point> predicted = display_.predicted_display_time();
  if (!predicted) throw std::logic_error("predicted flip clock: the display has predicted no flip");
  return start_offset_s_ + std::chrono::duration<double>(*predicted - start_).count();
}

}  // namespace glarelab

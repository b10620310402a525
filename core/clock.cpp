#include "core/clock.h"

#include <ctime>
#include <stdexcept>

namespace glarelab {

double process_cpu_time_s() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

MonotonicClock::MonotonicClock(double start_offset_s)
    : start_(std::chrono::steady_clock::now()), start_offset_s_(start_offset_s) {}

double MonotonicClock::now_s() const {
  return start_offset_s_ + std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

double MonotonicClock::on_flip_at(std::chrono::steady_clock::time_point presented) {
  return start_offset_s_ + std::chrono::duration<double>(presented - start_).count();
}

VirtualClock::VirtualClock(double refresh_hz, double start_s, std::int64_t start_frame)
    : period_s_(0.0), start_s_(start_s), frames_(start_frame) {
  if (!(refresh_hz > 0.0)) throw std::invalid_argument("VirtualClock: refresh_hz must be positive");
  period_s_ = 1.0 / refresh_hz;
}

// Time is computed from the frame count rather than accumulated, so it does not drift by
// rounding over a long session: flip k is at start_s + k / refresh_hz exactly.
double VirtualClock::now_s() const { return start_s_ + static_cast<double>(frames_) * period_s_; }

// Flip k (counting from 0) happens at start_s + k / refresh_hz.
double VirtualClock::on_flip() {
  const double flip_s = now_s();
  ++frames_;
  return flip_s;
}

}  // namespace glarelab

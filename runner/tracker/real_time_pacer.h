#pragma once
// Paces an offscreen run in real time when a live tracker is attached: after each frame, sleep
// until the next frame's deadline (start + k * period), so tracker time and session time stay
// comparable. A run without live devices keeps the virtual clock and runs as fast as it renders.
#include <chrono>
#include <cstdint>
#include <thread>

namespace glarelab {

class RealTimePacer {
 public:
  explicit RealTimePacer(double refresh_hz)
      : period_(std::chrono::duration<double>(1.0 / refresh_hz)), start_(std::chrono::steady_clock::now()) {}
  // Sleeps until frame k + 1 is due (late frames do not sleep; the schedule is not shifted).
  void wait_for_next_frame() {
    ++frames_;
    std::this_thread::sleep_until(start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                               period_ * static_cast<double>(frames_)));
  }

 private:
  std::chrono::duration<double> period_;
  std::chrono::steady_clock::time_point start_;
  std::int64_t frames_ = 0;
};

}  // namespace glarelab

#pragma once
// Paces an offscreen run in real time (a live tracker or response device attached, or --clock
// real): each present waits for the next refresh boundary (start + k * period), as a window's swap
// waits for the vertical blank, so flips are stamped on the refresh grid and tracker time and
// session time stay comparable. The flip is the boundary itself: the frame was ready before it, so
// a process the host wakes late after the boundary (a loaded machine holds it for a few to 100 ms
// now and then) does not move the flip, as a display's retrace does not wait for the program. A
// frame ready after its boundary waits for the next one: it flips a period late, and the session
// counts it dropped, as on a display. A run without live devices and without --clock real keeps
// the virtual clock and runs as fast as it renders.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <thread>

namespace glarelab {

class RealTimePacer {
 public:
  explicit RealTimePacer(double refresh_hz)
      : period_(std::chrono::duration<double>(1.0 / refresh_hz)), start_(std::chrono::steady_clock::now()) {}
  // Sleeps until the first refresh boundary after the last one waited for that is not yet past:
  // never two flips in one period, and no burst of flips to catch up after a late one. Returns
  // that boundary, the flip's time (SessionClock::on_flip_at).
  std::chrono::steady_clock::time_point wait_for_next_frame() {
    const double elapsed_periods = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_) / period_;
    boundary_ = std::max(boundary_ + 1, static_cast<std::int64_t>(std::ceil(elapsed_periods)));
    const auto at = start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                 period_ * static_cast<double>(boundary_));
    std::this_thread::sleep_until(at);
    return at;
  }
  std::int64_t boundary() const { return boundary_; }  // refresh boundaries since the start, of the last wait

 private:
  std::chrono::duration<double> period_;
  std::chrono::steady_clock::time_point start_;
  std::int64_t boundary_ = 0;
};

}  // namespace glarelab

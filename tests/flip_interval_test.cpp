// Timing that explains itself (issue: a lab's first study): a flip interval off the nominal period
// by more than 10 % is warned about with its likely cause, and late trial onsets are counted by
// what the session was doing before them (glare preparation, perception, drawing) or, when none
// of its own work took long enough, a host stall.
#include <gtest/gtest.h>

#include <string>

#include "runner/session/frame_timing.h"
#include "runner/session/refresh_rate_check.h"

namespace glarelab {
namespace {

TEST(FlipIntervalWarning, NamesTheLikelyCauseBeyondTenPercent) {
  const double period_s = 1.0 / 60.0;
  EXPECT_EQ(flip_interval_warning(60.0, period_s), "");
  EXPECT_EQ(flip_interval_warning(60.0, 1.09 * period_s), "");
  EXPECT_EQ(flip_interval_warning(60.0, 0.91 * period_s), "");
  // The new user's window: 2.41 ms against 16.67 ms, no vsync.
  const std::string no_vsync = flip_interval_warning(60.0, 0.00241);
  EXPECT_NE(no_vsync.find("2.41 ms, not every 16.67 ms"), std::string::npos) << no_vsync;
  EXPECT_NE(no_vsync.find("does not wait for the vertical blank"), std::string::npos) << no_vsync;
  // Two periods a frame: a compositor, or a 30 Hz display.
  const std::string doubled = flip_interval_warning(60.0, 2.02 * period_s);
  EXPECT_NE(doubled.find("each frame stays 2 refreshes"), std::string::npos) << doubled;
  EXPECT_NE(doubled.find("30 Hz"), std::string::npos) << doubled;
  // 50 Hz against 60: another rate.
  const std::string other = flip_interval_warning(60.0, 0.020);
  EXPECT_NE(other.find("refresh at 50 Hz"), std::string::npos) << other;
}

TEST(FlipIntervalWarning, LateOnsetsAreCountedByTheirCause) {
  FrameTimingMonitor monitor(60.0);
  const double p = 1.0 / 60.0;
  double t = 0.0;
  monitor.on_flip(t, 0, -1);
  // Onset 1: on time.
  monitor.on_flip(t += p, 0, 0);
  // Onset 2: 3 periods late (2 periods of delay) after 40 ms of glare frames: glare preparation.
  monitor.on_flip(t += p, 1, -1);
  monitor.add_work(FlipWork::glare_preparation, 0.040);
  monitor.add_work(FlipWork::drawing, 0.002);
  monitor.on_flip(t += 3 * p, 1, 0);
  // Onset 3: 2 periods late after 12 ms of perception stages (>= half the 16.7 ms delay).
  monitor.on_flip(t += p, 2, -1);
  monitor.add_work(FlipWork::perception, 0.012);
  monitor.on_flip(t += 2 * p, 2, 0);
  // Onset 4: late with only 1 ms of drawing: the host stalled.
  monitor.on_flip(t += p, 3, -1);
  monitor.add_work(FlipWork::drawing, 0.001);
  monitor.on_flip(t += 2 * p, 3, 0);
  // Work before an earlier flip is forgotten at that flip: onset 5 is late with none since.
  monitor.add_work(FlipWork::glare_preparation, 1.0);
  monitor.on_flip(t += p, 4, -1);
  monitor.on_flip(t += 2 * p, 4, 0);
  const FrameTimingSummary summary = monitor.summary();
  EXPECT_EQ(summary.late_onsets, 4);
  EXPECT_EQ(summary.late_onsets_by_cause[0], 1);  // glare preparation
  EXPECT_EQ(summary.late_onsets_by_cause[1], 1);  // perception
  EXPECT_EQ(summary.late_onsets_by_cause[2], 0);  // drawing
  EXPECT_EQ(summary.late_onsets_by_cause[3], 2);  // host stall
  EXPECT_NE(summary.describe().find("late onsets 4 (glare preparation 1, perception stages 1, host stall 2)"),
            std::string::npos)
      << summary.describe();
  // 9 intervals: 5 of one period, 3 of two, 1 of three: the median is one period.
  EXPECT_NEAR(summary.flip_interval_median_ms, 1000.0 * p, 1e-9);
}

}  // namespace
}  // namespace glarelab

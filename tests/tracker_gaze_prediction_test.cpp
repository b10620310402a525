// Latency compensation of gaze (runner/tracker/gaze_prediction.h) against hand-computed tracks:
// a straight-line track is extrapolated exactly, a fixation stays put, the extrapolation is limited
// and kept on the display, and only the samples of the fit window count.
#include <gtest/gtest.h>

#include "runner/tracker/gaze_prediction.h"

namespace glarelab {
namespace {

GazeTrack track_of(double x0, double vx, double y0, double vy, double from_s, double to_s, double rate_hz = 120.0) {
  GazeTrack track;
  for (int k = 0; from_s + k / rate_hz <= to_s + 1e-12; ++k) {
    const double t = from_s + k / rate_hz;
    track.add({t, x0 + vx * t, y0 + vy * t});
  }
  return track;
}

TEST(GazePrediction, AStraightTrackIsExtrapolatedExactly) {
  // x = 0.2 + 0.5 t, y = 0.6 - 0.25 t, sampled at 120 Hz up to t = 1 s; predicted at 1.03 s.
  const GazeTrack track = track_of(0.2, 0.5, 0.6, -0.25, 0.9, 1.0);
  const auto predicted = track.predicted(1.03);
  ASSERT_TRUE(predicted.has_value());
  EXPECT_NEAR(predicted->x, 0.2 + 0.5 * 1.03, 1e-12);
  EXPECT_NEAR(predicted->y, 0.6 - 0.25 * 1.03, 1e-12);
  EXPECT_DOUBLE_EQ(predicted->session_time_s, 1.03);
}

TEST(GazePrediction, AFixationStaysWhereItIs) {
  const GazeTrack track = track_of(0.4, 0.0, 0.3, 0.0, 5.0, 5.2);
  const auto predicted = track.predicted(5.25);
  EXPECT_NEAR(predicted->x, 0.4, 1e-12);
  EXPECT_NEAR(predicted->y, 0.3, 1e-12);
}

TEST(GazePrediction, TooFewSamplesOrNoTimeAheadGiveTheNewestSample) {
  GazeTrack track;
  EXPECT_FALSE(track.predicted(1.0).has_value());
  track.add({0.0, 0.1, 0.1});
  track.add({0.01, 0.2, 0.2});
  EXPECT_DOUBLE_EQ(track.predicted(0.05)->x, 0.2);  // two samples: below min_samples = 3
  track.add({0.02, 0.3, 0.3});
  EXPECT_DOUBLE_EQ(track.predicted(0.02)->x, 0.3);  // not after the newest sample
  EXPECT_NEAR(track.predicted(0.03)->x, 0.4, 1e-12);
}

TEST(GazePrediction, ExtrapolationIsLimitedAndStaysOnTheDisplay) {
  // 0.5 per second: 1 s ahead would reach 1.1; the limit (0.1 s) gives 0.6 + 0.05.
  const GazeTrack slow = track_of(0.1, 0.5, 0.5, 0.0, 0.95, 1.0);
  EXPECT_NEAR(slow.predicted(2.0)->x, 0.1 + 0.5 * 1.1, 1e-12);
  // 8 per second toward the right edge from 0.9: 0.1 s ahead would be 1.7; kept at 1.
  const GazeTrack fast = track_of(0.9 - 8.0, 8.0, 0.5, 0.0, 0.96, 1.0);
  EXPECT_DOUBLE_EQ(fast.predicted(1.1)->x, 1.0);
}

TEST(GazePrediction, OnlyTheFitWindowCounts) {
  // A saccade from 0.3 to 0.7 at t = 0.2 s; 100 ms later only the new fixation is in the 50 ms window.
  GazeTrack track;
  for (int k = 0; k <= 36; ++k) {
    const double t = k / 120.0;
    track.add({t, t < 0.2 ? 0.3 : 0.7, 0.5});
  }
  EXPECT_NEAR(track.predicted(0.35)->x, 0.7, 1e-12);
}

}  // namespace
}  // namespace glarelab

// A binocular tracker's samples per eye (runner/tracker/tracker_session.h): each eye's own
// filtered pupil, latest gaze and blinks, from a replayed track whose eyes differ, against the
// values written into the track.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "core/clock.h"
#include "runner/tracker/tracker_session.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

TEST(StereoTrackerTest, EachEyeKeepsItsOwnPupilGazeAndBlinks) {
  const test::ScratchDir dir;
  // 120 Hz per eye for 2 s: the left eye (id 1) 3 mm looking at (0.25, 0.4) with a blink from
  // 1.0 s to 1.2 s; the right eye (id 0) 6 mm looking at (0.75, 0.6), never blinking.
  std::ostringstream csv;
  csv << "eye,device_time_s,session_time_s,pupil_diameter_mm,gaze_x,gaze_y,confidence,valid\n";
  for (int k = 0; k < 240; ++k) {
    const double t = k / 120.0;
    const bool blink = t >= 1.0 - 1e-9 && t < 1.2 - 1e-9;
    csv << "0," << t << "," << t << ",6,0.75,0.6,0.95,1\n";
    if (blink)
      csv << "1," << t << "," << t << ",0,-1,-1,0,0\n";
    else
      csv << "1," << t << "," << t << ",3,0.25,0.4,0.95,1\n";
  }
  const auto path = dir.path() / "track.csv";
  test::write_bytes(path.string(), csv.str());
  TrackerOptions options;
  options.spec = "replay:" + path.string();
  TrackerSession session(options, 1);
  VirtualClock clock(60.0);
  ASSERT_FALSE(session.start(clock).has_value());
  EXPECT_FALSE(session.measured_eye_pupil_mm(0).has_value());
  for (int frame = 0; frame <= 2 * 60; ++frame) session.on_frame(frame / 60.0);

  // A constant diameter passes the low-pass unchanged.
  ASSERT_TRUE(session.measured_eye_pupil_mm(1).has_value());
  ASSERT_TRUE(session.measured_eye_pupil_mm(0).has_value());
  EXPECT_NEAR(*session.measured_eye_pupil_mm(1), 3.0, 1e-9);
  EXPECT_NEAR(*session.measured_eye_pupil_mm(0), 6.0, 1e-9);
  EXPECT_NEAR(*session.measured_pupil_mm(), 4.5, 1e-9);  // the mono model pupil: their mean

  ASSERT_TRUE(session.latest_eye_gaze(1).has_value());
  EXPECT_EQ(session.latest_eye_gaze(1)->x, 0.25);
  EXPECT_EQ(session.latest_eye_gaze(1)->y, 0.4);
  EXPECT_EQ(session.latest_eye_gaze(0)->x, 0.75);
  EXPECT_EQ(session.latest_eye_gaze(0)->y, 0.6);
  EXPECT_EQ(session.predicted_eye_gaze(0, 2.0)->x, 0.75);

  // The left eye's blink: from its first sample in the blink to its first sample out of it.
  const auto& left = session.detected_eye_blinks(1);
  ASSERT_EQ(left.size(), 1u);
  EXPECT_NEAR(left[0].onset_s, 1.0, 1e-9);
  EXPECT_NEAR(left[0].offset_s, 1.2, 1e-9);
  EXPECT_TRUE(session.detected_eye_blinks(0).empty());
  // Both eyes closed never: the mono detection (every eye in a blink) finds none.
  EXPECT_TRUE(session.detected_blinks().empty());
}

}  // namespace
}  // namespace glarelab

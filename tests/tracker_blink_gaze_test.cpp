// One blink schedule and the tracker's inputs to the glare engine: the simulated tracker blinks
// exactly when the eye model's lids move (same seed), a session's tracker turns its samples into
// detected blinks and a latest gaze, and replayed gaze comes through as recorded.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <vector>

#include "glare/eye/eye_model.h"
#include "core/clock.h"
#include "runner/tracker/simulated_tracker.h"
#include "runner/tracker/tracker_session.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

constexpr double kRateHz = 120.0;

// Runs of blink samples (confidence 0) of eye 0 as [first blink sample, first sample after).
std::vector<std::pair<double, double>> blink_runs(const TrackerBatch& batch) {
  std::vector<std::pair<double, double>> runs;
  bool in_blink = false;
  for (const TrackerSample& sample : batch.samples) {
    if (sample.eye != 0) continue;
    if (!sample.valid && !in_blink) runs.emplace_back(sample.session_time_s, INFINITY);
    if (sample.valid && in_blink) runs.back().second = sample.session_time_s;
    in_blink = !sample.valid;
  }
  return runs;
}

TEST(TrackerBlinkSchedule, SimulatedBlinksAreTheEyeModelsLidClosuresForTheSameSeed) {
  const std::uint64_t seed = 13;
  SimulatedTracker tracker(seed);
  VirtualClock clock(60.0);
  tracker.start(clock);
  const TrackerBatch batch = tracker.poll(30.0);
  const EyeModel eye(EyeParameters{}, seed);  // what `glarelab eye-trace --seed 13` prints
  for (const TrackerSample& sample : batch.samples)
    ASSERT_EQ(!sample.valid, eye.state_at(sample.session_time_s).blink_closure > 0.0) << sample.session_time_s;
  // Interval by interval: each run of blink samples starts at the first sample after the lids begin
  // to close and ends at the first sample after they are open again.
  const std::vector<std::pair<double, double>> runs = blink_runs(batch);
  const EyelidModel& lids = eye.eyelids();
  std::size_t matched = 0;
  for (std::int64_t k = 0; lids.blink_end_s(k) < 30.0; ++k) {
    ASSERT_LT(matched, runs.size());
    const double onset_s = lids.blink_onset_s(k), end_s = lids.blink_end_s(k);
    EXPECT_GT(runs[matched].first, onset_s) << "blink " << k;
    EXPECT_LE(runs[matched].first, onset_s + 1.0 / kRateHz) << "blink " << k;
    EXPECT_GE(runs[matched].second, end_s) << "blink " << k;
    EXPECT_LE(runs[matched].second, end_s + 1.0 / kRateHz) << "blink " << k;
    ++matched;
  }
  EXPECT_GE(matched, 7u) << "17 blinks a minute";
  EXPECT_EQ(matched, runs.size());
  // Another seed blinks at other times.
  EXPECT_NE(EyelidModel(EyeParameters{}, 14).blink_onset_s(0), lids.blink_onset_s(0));
}

TEST(TrackerBlinkSchedule, SessionDetectsTheBlinksAndKeepsTheLatestConfidentGaze) {
  const std::uint64_t seed = 13;
  TrackerOptions options;
  options.spec = "simulated";
  TrackerSession session(options, seed);
  VirtualClock clock(60.0);
  ASSERT_FALSE(session.start(clock).has_value());
  EXPECT_FALSE(session.latest_gaze().has_value());
  EXPECT_FALSE(session.measured_pupil_mm().has_value());
  const SimulatedTracker reference(seed);
  const EyelidModel& lids = reference.eyelids();
  for (int frame = 0; frame <= 20 * 60; ++frame) {
    const double t = frame / 60.0;
    session.on_frame(t);
    // The latest gaze is that of the last sample not in a blink (both eyes report the same gaze).
    auto k = static_cast<std::int64_t>(std::floor(t * kRateHz + 1e-9));
    while (reference.blinking(static_cast<double>(k) / kRateHz)) --k;
    const TrackerSample last = reference.sample(k, 1);
    ASSERT_TRUE(session.latest_gaze().has_value());
    ASSERT_EQ(session.latest_gaze()->x, last.gaze_x) << t;
    ASSERT_EQ(session.latest_gaze()->y, last.gaze_y) << t;
    ASSERT_EQ(session.latest_gaze()->session_time_s, last.session_time_s) << t;
  }
  ASSERT_TRUE(session.measured_pupil_mm().has_value());
  EXPECT_GT(*session.measured_pupil_mm(), 1.5);
  const std::vector<TrackerBlinkInterval>& blinks = session.detected_blinks();
  std::size_t count = 0;
  for (std::int64_t k = 0; lids.blink_end_s(k) < 20.0; ++k, ++count) {
    ASSERT_LT(count, blinks.size());
    EXPECT_GT(blinks[count].onset_s, lids.blink_onset_s(k));
    EXPECT_LE(blinks[count].onset_s, lids.blink_onset_s(k) + 1.0 / kRateHz);
    EXPECT_GE(blinks[count].offset_s, lids.blink_end_s(k));
    EXPECT_LE(blinks[count].offset_s, lids.blink_end_s(k) + 1.0 / kRateHz);
  }
  EXPECT_GE(count, 4u);
  // A blink in progress at 20 s would be the last, still open.
  EXPECT_LE(blinks.size(), count + 1);
  session.finish(20.0);
}

TEST(TrackerBlinkSchedule, ReplayedGazeIsTheRecordedGaze) {
  test::ScratchDir dir;
  const auto csv = dir.path() / "gaze.csv";
  std::ofstream(csv) << "eye,device_time_s,session_time_s,pupil_diameter_mm,gaze_x,gaze_y,confidence,valid\n"
                        "0,10.0,0.10,4.0,0.25,0.75,0.9,1\n"
                        "0,10.1,0.20,4.1,0.30,0.70,0.3,1\n"  // below the filter's 0.6: not taken
                        "0,10.2,0.30,,,,0.0,0\n"
                        "0,10.3,0.40,4.2,,,0.9,1\n";          // no gaze in it
  TrackerOptions options;
  options.spec = "replay:" + csv.string();
  TrackerSession session(options, 1);
  VirtualClock clock(60.0);
  ASSERT_FALSE(session.start(clock).has_value());
  session.on_frame(0.15);
  ASSERT_TRUE(session.latest_gaze().has_value());
  EXPECT_EQ(session.latest_gaze()->x, 0.25);
  EXPECT_EQ(session.latest_gaze()->y, 0.75);
  session.on_frame(0.5);
  EXPECT_EQ(session.latest_gaze()->x, 0.25);
  EXPECT_EQ(session.latest_gaze()->session_time_s, 0.10);
  // One eye only, a confidence drop at 0.2 s and an invalid sample at 0.3 s: one blink 0.2-0.4 s.
  ASSERT_EQ(session.detected_blinks().size(), 1u);
  EXPECT_EQ(session.detected_blinks()[0].onset_s, 0.20);
  EXPECT_EQ(session.detected_blinks()[0].offset_s, 0.40);
  session.finish(0.5);
}

}  // namespace
}  // namespace glarelab

// `glarelab run --tracker simulated` end to end: every sample up to the end of the session is
// logged, equal to the simulated tracker computed here (a second path to the same values), and
// the calibration screens run and record their outcome.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "cli_process.h"
#include "runner/store/result_store.h"
#include "runner/tracker/replay_tracker.h"
#include "runner/tracker/simulated_tracker.h"
#include "scratch_dir.h"
#include "session_events.h"

namespace glarelab {
namespace {

TEST(TrackerSimulatedRun, LogsEverySampleOfTheSessionAndTheCalibration) {
  test::ScratchDir dir;
  const auto experiment = test::demo_variant(dir.path(), {});
  const std::string db = (dir.path() / "sim.db").string();
  const auto run = test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer", "simulated",
                                       "--db", db, "--seed", "11", "--tracker", "simulated", "--pupil-model",
                                       "calibrated", "--pupil-calibration-s", "0.5", "--stop-after", "2"},
                                      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  // 30 + 30 calibration frames and 2 trials of 30 frames on the virtual clock: the session ends at
  // 120 / 60 Hz = 2 s, so samples k = 0..240 of each eye (t = k / 120 s <= 2 s) are logged.
  const RecordedTrack logged = read_tracker_database(db, 1);
  ASSERT_EQ(logged.samples.size(), 2u * 241u);
  SimulatedTracker reference(11);
  for (std::size_t i = 0; i < logged.samples.size(); ++i) {
    const TrackerSample expected = reference.sample(static_cast<std::int64_t>(i / 2), static_cast<int>(i % 2));
    ASSERT_EQ(logged.samples[i].session_time_s, expected.session_time_s) << i;
    ASSERT_EQ(logged.samples[i].pupil_diameter_mm, expected.pupil_diameter_mm) << i;
  }
  // The simulated pupil follows its own field luminance, not the screens: the calibration must
  // notice that and fall back to the measured diameter.
  EXPECT_NE(run.output.find("tracker simulated (seed 11"), std::string::npos) << run.output;
  const ResultStore store(db);
  const std::vector<std::string> messages = test::session_event_messages(store, "pupil_calibration");
  ASSERT_EQ(messages.size(), 1u);
  EXPECT_NE(messages[0].find("did not respond"), std::string::npos) << messages[0];
  // Polled at each flip: the black screen (flips 0..29, t <= 29/60 s) sees samples k = 0..58 of
  // both eyes (118), the white one (flips 30..59) k = 59..118 (120); no blink falls in them.
  EXPECT_NE(messages[0].find("(120 and 118 accepted samples)"), std::string::npos) << messages[0];
}

std::vector<std::string> event_messages(const std::string& db, const std::string& kind) {
  return test::session_event_messages(db, kind);
}

// Every row dynamic, a 64 px gaze window, blinks from the tracker: the session logs its glare
// backend and inputs once and the window of every trial, centred on the tracker's gaze (the first
// trial is prepared before any flip: the tracker is read then, at t = 0).
TEST(TrackerSimulatedRun, GazeWindowFollowsTheTrackerAndIsLoggedPerTrial) {
  test::ScratchDir dir;
  const auto experiment =
      test::small_dynamic_demo(dir.path(), "backend = \"cpu\"\ngaze_window_px = 64\nblink_source = \"tracker\"\n"
                                           "model = \"ritschel\"\n"  // the gaze window is the wave-optics eye's
                                           "presentation = \"prepared\"");  // one gaze a trial, whatever the machine's speed
  const std::string tracked_db = (dir.path() / "tracked.db").string();
  const auto tracked = test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer", "simulated",
                                           "--db", tracked_db, "--seed", "5", "--tracker", "simulated", "--stop-after", "2"},
                                          dir.path());
  ASSERT_EQ(tracked.exit_code, 0) << tracked.output;
  const auto backend = event_messages(tracked_db, "glare_backend");
  ASSERT_EQ(backend.size(), 1u);
  EXPECT_NE(backend[0].find("glare backend cpu float64: asked for by name"), std::string::npos) << backend[0];
  const auto inputs = event_messages(tracked_db, "glare_inputs");
  ASSERT_EQ(inputs.size(), 1u);
  EXPECT_NE(inputs[0].find("pupil: the tracker's filtered pupil"), std::string::npos) << inputs[0];
  EXPECT_NE(inputs[0].find("blinks: detected by the tracker"), std::string::npos) << inputs[0];
  EXPECT_NE(inputs[0].find("gaze window 64 px around the tracker's latest gaze"), std::string::npos) << inputs[0];
  const auto windows = event_messages(tracked_db, "glare_window");
  ASSERT_EQ(windows.size(), 2u);
  // Trial 0: the latest sample at t = 0 is k = 0 of the left eye (issue 33: it was the display
  // centre, 224, 96, before the tracker had been read).
  const auto window_of = [](const TrackerSample& sample) {
    const int x0 = std::clamp(static_cast<int>(std::lround(sample.gaze_x * 512 - 32)), 0, 512 - 64);
    const int y0 = std::clamp(static_cast<int>(std::lround(sample.gaze_y * 256 - 32)), 0, 256 - 64);
    return "gaze window 64x64 px at (" + std::to_string(x0) + ", " + std::to_string(y0) + "), centred on gaze (" +
           std::to_string(sample.gaze_x) + ", " + std::to_string(sample.gaze_y) + ") from the tracker";
  };
  const TrackerSample first = SimulatedTracker(5).sample(0, 1);
  ASSERT_TRUE(first.valid);
  EXPECT_NE(windows[0].find("trial 0 (dynamic): " + window_of(first)), std::string::npos) << windows[0];
  // Trial 1 is prepared after trial 0's two flips (t = 0, 1/60 s): the latest sample is k = 2 at
  // 1/60 s; its gaze is the simulated tracker's first fixation.
  const TrackerSample sample = SimulatedTracker(5).sample(2, 1);
  ASSERT_TRUE(sample.valid);
  const int x0 = std::clamp(static_cast<int>(std::lround(sample.gaze_x * 512 - 32)), 0, 512 - 64);
  const int y0 = std::clamp(static_cast<int>(std::lround(sample.gaze_y * 256 - 32)), 0, 256 - 64);
  EXPECT_NE(windows[1].find("trial 1 (dynamic): gaze window 64x64 px at (" + std::to_string(x0) + ", " +
                            std::to_string(y0) + "), centred on gaze (" + std::to_string(sample.gaze_x) + ", " +
                            std::to_string(sample.gaze_y) + ") from the tracker"),
            std::string::npos)
      << windows[1];

  // Without a tracker: the display centre, said once for the session and in each trial's line.
  const std::string plain_db = (dir.path() / "plain.db").string();
  const auto plain = test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer", "simulated",
                                         "--db", plain_db, "--seed", "5", "--stop-after", "1"},
                                        dir.path());
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  const auto plain_inputs = event_messages(plain_db, "glare_inputs");
  ASSERT_EQ(plain_inputs.size(), 1u);
  EXPECT_NE(plain_inputs[0].find("the display centre: no tracker, no gaze"), std::string::npos) << plain_inputs[0];
  EXPECT_NE(plain_inputs[0].find("(no tracker: the model's)"), std::string::npos) << plain_inputs[0];
  const auto plain_windows = event_messages(plain_db, "glare_window");
  ASSERT_EQ(plain_windows.size(), 1u);
  EXPECT_NE(plain_windows[0].find("the display centre (no gaze)"), std::string::npos) << plain_windows[0];
}

}  // namespace
}  // namespace glarelab

// `glarelab run --tracker simulated` end to end: every sample up to the end of the session is
// logged, equal to the simulated tracker computed here (a second path to the same values), and
// the calibration screens run and record their outcome.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include "cli_process.h"
#include "runner/store/result_store.h"
#include "runner/tracker/replay_tracker.h"
#include "runner/tracker/simulated_tracker.h"
#include "scratch_dir.h"

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
  sqlite3_stmt* statement = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(store.handle(), "SELECT message FROM session_events WHERE kind = 'pupil_calibration'",
                               -1, &statement, nullptr),
            SQLITE_OK);
  std::vector<std::string> messages;
  while (sqlite3_step(statement) == SQLITE_ROW)
    messages.emplace_back(reinterpret_cast<const char*>(sqlite3_column_text(statement, 0)));
  sqlite3_finalize(statement);
  ASSERT_EQ(messages.size(), 1u);
  EXPECT_NE(messages[0].find("did not respond"), std::string::npos) << messages[0];
  // Polled at each flip: the black screen (flips 0..29, t <= 29/60 s) sees samples k = 0..58 of
  // both eyes (118), the white one (flips 30..59) k = 59..118 (120); no blink falls in them.
  EXPECT_NE(messages[0].find("(120 and 118 accepted samples)"), std::string::npos) << messages[0];
}

}  // namespace
}  // namespace glarelab

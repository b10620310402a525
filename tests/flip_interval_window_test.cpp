// A window without vsync (Xvfb has no retrace, tests/CMakeLists.txt runs these under xvfb-run):
// timing-test and run warn that the flips do not follow the refresh, naming the cause, exactly when
// the flips they stored depart from the nominal period by more than 10 %.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include "cli_process.h"
#include "runner/store/result_store.h"
#include "scratch_dir.h"
#include "session_events.h"

namespace glarelab {
namespace {

// The stored flips' intervals of a session, and the nominal period, from its frames.
std::vector<double> flip_intervals_s(const std::string& db) {
  const ResultStore store(db);
  std::vector<double> flips;
  for (const TrialRecord& trial : store.load_trials(store.load_sessions().at(0).id))
    for (const FrameRecord& frame : store.load_frames(trial.id)) flips.push_back(frame.flip_s);
  std::sort(flips.begin(), flips.end());
  std::vector<double> intervals;
  for (std::size_t i = 1; i < flips.size(); ++i) intervals.push_back(flips[i] - flips[i - 1]);
  return intervals;
}

TEST(WindowBackendFlipInterval, TimingTestWarnsWhenTheMeanIntervalIsOffTheRefresh) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "WindowBackend tests run under xvfb-run (see tests/CMakeLists.txt)";
  const test::ScratchDir dir;
  const std::string db = dir.file("rig.db");
  const auto run = test::run_glarelab(
      {"timing-test", "--display", "window", "--frames", "120", "--width", "320", "--height", "200", "--db", db},
      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<double> intervals = flip_intervals_s(db);
  double mean_s = 0.0;
  for (double interval : intervals) mean_s += interval / static_cast<double>(intervals.size());
  const ResultStore store(db);
  const auto display = test::session_event_messages(store, "display");
  ASSERT_EQ(display.size(), 1u);
  const auto at = display[0].find("; refresh ");
  ASSERT_NE(at, std::string::npos) << display[0];
  const double refresh_hz = std::stod(display[0].substr(at + 10));
  const double departure = std::abs(mean_s * refresh_hz - 1.0);
  std::printf("Xvfb: mean flip interval %.3f ms against %.3f ms (%.0f %% off)\n", 1000.0 * mean_s, 1000.0 / refresh_hz,
              100.0 * departure);
  const bool warned = run.output.find("warning: the flips come every ") != std::string::npos;
  EXPECT_EQ(warned, departure > 0.10) << run.output;
  EXPECT_EQ(test::session_event_messages(store, "flip_interval").size(), departure > 0.10 ? 1u : 0u);
  // Xvfb has no retrace: the swap does not wait, and the warning says so.
  EXPECT_GT(departure, 0.10) << "Xvfb flipped at the refresh rate: this test needs a display without vsync";
  if (warned && mean_s * refresh_hz < 1.0) {
    EXPECT_NE(run.output.find("does not wait for the vertical blank"), std::string::npos) << run.output;
  }
}

TEST(WindowBackendFlipInterval, RunWarnsWhenTheMedianIntervalIsOffTheRefresh) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "WindowBackend tests run under xvfb-run (see tests/CMakeLists.txt)";
  const test::ScratchDir dir;
  test::write_demo_conditions_without_glare(dir.path() / "conditions.csv");
  const auto experiment = test::demo_variant(dir.path(), {{"file", "file = \"" + (dir.path() / "conditions.csv").string() + "\""},
                                                          {"width_px", "width_px = 512"},
                                                          {"height_px", "height_px = 256"},
                                                          {"stimulus_frames", "stimulus_frames = 6"}});
  const std::string db = dir.file("run.db");
  const auto run = test::run_glarelab({"run", experiment.string(), "--display", "window", "--observer", "simulated",
                                       "--db", db},
                                      dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::vector<double> intervals = flip_intervals_s(db);
  ASSERT_GT(intervals.size(), 4u);
  std::nth_element(intervals.begin(), intervals.begin() + static_cast<std::ptrdiff_t>(intervals.size() / 2), intervals.end());
  const double median_s = intervals[intervals.size() / 2];
  const double departure = std::abs(median_s * 60.0 - 1.0);
  std::printf("Xvfb run: median flip interval %.3f ms against 16.667 ms\n", 1000.0 * median_s);
  EXPECT_EQ(run.output.find("warning: the flips come every ") != std::string::npos, departure > 0.10) << run.output;
  EXPECT_EQ(test::session_event_messages(db, "flip_interval").size(), departure > 0.10 ? 1u : 0u);
  EXPECT_GT(departure, 0.10) << "Xvfb flipped at the refresh rate: this test needs a display without vsync";
}

}  // namespace
}  // namespace glarelab

// Dropped-frame detection and the session's frame-timing summary: unit checks on hand-made flip
// times, and whole offscreen sessions with the virtual clock, with and without injected slow flips.
#include <gtest/gtest.h>

#include <sqlite3.h>

#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "runner/session/frame_timing.h"
#include "runner/session/session_runner.h"
#include "runner/store/result_store.h"
#include "cli_process.h"

namespace glarelab {
namespace {

TEST(FrameTimingMonitor, CountsFlipsLaterThanOneAndAHalfPeriods) {
  FrameTimingMonitor monitor(100.0);  // 10 ms period
  // Trial 0: frames at 0, 10, 20 (on time), 36 (16 ms: late), 51 (15 ms: exactly 1.5, not late).
  EXPECT_FALSE(monitor.on_flip(0.000, 0, 0));
  EXPECT_FALSE(monitor.on_flip(0.010, 0, 1));
  EXPECT_FALSE(monitor.on_flip(0.020, 0, 2));
  EXPECT_TRUE(monitor.on_flip(0.036, 0, 3));
  EXPECT_FALSE(monitor.on_flip(0.0505, 0, 4));
  // A response-screen flip, then trial 1's onset 13 ms later: 3 ms of onset jitter, not a drop.
  monitor.on_flip(0.0605, 0, -1);
  EXPECT_FALSE(monitor.on_flip(0.0735, 1, 0));
  EXPECT_TRUE(monitor.on_flip(0.1035, 1, 1));  // 30 ms
  const FrameTimingSummary s = monitor.summary();
  EXPECT_EQ(s.frames_shown, 7);
  EXPECT_EQ(s.frames_dropped, 2);
  EXPECT_EQ(s.onsets, 1);
  EXPECT_NEAR(s.onset_jitter_mean_ms, 3.0, 1e-9);
  EXPECT_NEAR(s.onset_jitter_max_ms, 3.0, 1e-9);
  ASSERT_EQ(monitor.dropped().size(), 2u);
  EXPECT_EQ(monitor.dropped()[1].trial_index, 1);
  EXPECT_EQ(monitor.dropped()[1].frame_index, 1);
  EXPECT_NEAR(monitor.dropped()[1].interval_s, 0.030, 1e-12);
}

// A late onset is no dropped frame, but it is reported with its interval, its likely cause (the
// session's work that covers half the lateness, else a host stall) and that work by kind.
TEST(FrameTimingMonitor, ALateOnsetIsReportedWithItsCauseAndTheSessionsWorkMeanwhile) {
  FrameTimingMonitor monitor(100.0);  // 10 ms period
  monitor.on_flip(0.000, 0, 0);
  monitor.on_flip(0.010, 0, -1);
  EXPECT_FALSE(monitor.on_flip(0.020, 1, 0));  // on time
  EXPECT_FALSE(monitor.late_onset().has_value());
  monitor.on_flip(0.030, 1, -1);
  // 40 ms late; 4 ms of drawing is not half of it: the host held the process.
  monitor.add_work(FlipWork::drawing, 0.004);
  EXPECT_FALSE(monitor.on_flip(0.080, 2, 0)) << "an onset is not a dropped frame";
  ASSERT_TRUE(monitor.late_onset().has_value());
  EXPECT_NEAR(monitor.late_onset()->interval_s, 0.050, 1e-12);
  EXPECT_EQ(monitor.late_onset()->cause, kHostStallCause);
  EXPECT_EQ(monitor.late_onset()->describe(2),
            "trial 2 onset: 50.000 ms since the previous flip (host stall); the session's work since that flip: "
            "glare preparation 0.000 ms, perception stages 0.000 ms, drawing 4.000 ms, recording the trial 0.000 ms");
  monitor.on_flip(0.090, 2, 1);
  EXPECT_FALSE(monitor.late_onset().has_value()) << "only the onset's own flip reports it";
  // 30 ms late; 25 ms of waiting for glare frames covers half of it.
  monitor.add_work(FlipWork::glare_preparation, 0.025);
  monitor.add_work(FlipWork::recording, 0.002);
  monitor.on_flip(0.130, 3, 0);
  ASSERT_TRUE(monitor.late_onset().has_value());
  EXPECT_EQ(monitor.late_onset()->cause, static_cast<int>(FlipWork::glare_preparation));
  EXPECT_NEAR(monitor.late_onset()->work_s[static_cast<int>(FlipWork::glare_preparation)], 0.025, 1e-15);
  EXPECT_NEAR(monitor.late_onset()->work_s[static_cast<int>(FlipWork::recording)], 0.002, 1e-15);
  monitor.on_timed_flip(0.140);
  EXPECT_FALSE(monitor.late_onset().has_value());
  EXPECT_EQ(monitor.summary().late_onsets, 2);
  EXPECT_EQ(monitor.summary().late_onsets_by_cause[kHostStallCause], 1);
}

struct SessionCounts {
  RunResult result;
  std::int64_t dropped_in_frames_table = 0;
  std::int64_t dropped_events = 0;
  std::int64_t frames_in_table = 0;
  std::string summary_event;
  std::vector<std::string> presentation_events;
};

SessionCounts run_demo(const test::ScratchDir& scratch, std::optional<int> slow_flip_every,
                       const std::vector<std::pair<std::string, std::string>>& more_keys = {}) {
  std::vector<std::pair<std::string, std::string>> keys = {{"stimulus_frames", "stimulus_frames = 5"},
                                                           {"repetitions", "repetitions = 1"}};
  keys.insert(keys.end(), more_keys.begin(), more_keys.end());
  const auto experiment = test::demo_variant(scratch.path(), keys);
  RunOptions options;
  options.experiment_path = experiment.string();
  options.display = "offscreen";
  options.observer = "simulated";
  options.db_path = (scratch.path() / "timing.db").string();
  options.slow_flip_every = slow_flip_every;
  std::ostringstream progress;
  SessionCounts counts;
  counts.result = run_session(options, progress);
  const ResultStore store(options.db_path);
  for (const TrialRecord& trial : store.load_trials(counts.result.session_id)) {
    for (const FrameRecord& frame : store.load_frames(trial.id)) {
      ++counts.frames_in_table;
      counts.dropped_in_frames_table += frame.dropped;
    }
  }
  sqlite3_stmt* statement = nullptr;
  if (sqlite3_prepare_v2(store.handle(), "SELECT kind || ':' || message FROM session_events ORDER BY id", -1,
                         &statement, nullptr) != SQLITE_OK)
    throw std::runtime_error(sqlite3_errmsg(store.handle()));
  while (sqlite3_step(statement) == SQLITE_ROW) {
    const std::string line = reinterpret_cast<const char*>(sqlite3_column_text(statement, 0));
    if (line.rfind("dropped_frame:", 0) == 0) ++counts.dropped_events;
    if (line.rfind("frame_timing:", 0) == 0) counts.summary_event = line;
    if (line.rfind("presentation_mode:", 0) == 0) counts.presentation_events.push_back(line.substr(18));
  }
  sqlite3_finalize(statement);
  return counts;
}

TEST(FrameTiming, VirtualClockSessionDropsNothing) {
  const test::ScratchDir scratch;
  const SessionCounts counts = run_demo(scratch, std::nullopt);
  ASSERT_EQ(counts.result.status, "completed");
  EXPECT_EQ(counts.result.frames_dropped, 0);
  EXPECT_EQ(counts.dropped_in_frames_table, 0);
  EXPECT_EQ(counts.dropped_events, 0);
  EXPECT_EQ(counts.result.frames_shown, counts.frames_in_table);
  EXPECT_EQ(counts.frames_in_table, 5 * counts.result.trials_in_design);
  EXPECT_NE(counts.summary_event.find("dropped 0;"), std::string::npos) << counts.summary_event;
}

// Every 7th flip arrives one period late. Offscreen simulated sessions flip only stimulus
// frames (5 per trial), so flip n (1-based) is frame (n - 1) % 5 of its trial; a delayed flip is a
// dropped frame unless it is a trial's onset (frame 0), which counts as onset jitter instead.
TEST(FrameTiming, InjectedSlowFlipsAreCountedWithTheirTrial) {
  const test::ScratchDir scratch;
  const SessionCounts counts = run_demo(scratch, 7);
  ASSERT_EQ(counts.result.status, "completed");
  const std::int64_t flips = 5 * counts.result.trials_in_design;
  std::int64_t expected_drops = 0;
  for (std::int64_t n = 7; n <= flips; n += 7) expected_drops += ((n - 1) % 5) != 0;
  EXPECT_GT(expected_drops, 0);
  EXPECT_EQ(counts.result.frames_dropped, expected_drops);
  EXPECT_EQ(counts.dropped_in_frames_table, expected_drops);
  EXPECT_EQ(counts.dropped_events, expected_drops);
  EXPECT_NE(counts.summary_event.find("dropped " + std::to_string(expected_drops) + ";"), std::string::npos)
      << counts.summary_event;
}

// [glare] presentation = "auto" settles the demo's layout live after its first glare trial; when
// a live trial then drops glare frames (here every 7th flip comes a period late), the layout goes
// back to prepared frames from the next trial on, once, and the log says why with the counts.
TEST(FrameTiming, AutoTakesALayoutBackToPreparedFramesWhenLiveFramesDrop) {
  // A small glare grid on a 2 Hz display: a glare frame and its drawing cost a few ms of the
  // program's own work against a 375 ms budget, so "auto" settles the layout live however loaded
  // the machine is. The cost is measured on the wall clock, which a loaded host stretches: at 60 Hz
  // with the demo's grid a loaded 2-core machine measured 14 ms, past the 12.5 ms budget; at 30 Hz,
  // with four builds on the two cores, 24 ms for the frame and 18 ms to draw it, past 25 ms; at
  // 10 Hz (75 ms) the test still failed one run in twelve under load 8 to 20. The session runs on the
  // virtual clock, so the slower refresh costs no wall time.
  // The wave-optics eye alone, the frame whose cost this budget was measured on.
  const std::vector<std::pair<std::string, std::string>> keys = {{"grid_px", "grid_px = 128\nmodel = \"ritschel\""},
                                                                 {"refresh_hz", "refresh_hz = 2.0"}};
  const test::ScratchDir calm_scratch;
  const SessionCounts calm = run_demo(calm_scratch, std::nullopt, keys);
  ASSERT_EQ(calm.presentation_events.size(), 1u);
  ASSERT_EQ(calm.presentation_events[0].rfind("glare trials: live from trial ", 0), 0u) << calm.presentation_events[0];

  const test::ScratchDir scratch;
  const SessionCounts counts = run_demo(scratch, 7, keys);
  ASSERT_EQ(counts.result.status, "completed");
  ASSERT_EQ(counts.presentation_events.size(), 2u);
  // The same settling as without the slow flips (the costs after the ';' are measured afresh).
  EXPECT_EQ(counts.presentation_events[0].substr(0, counts.presentation_events[0].find(';')),
            calm.presentation_events[0].substr(0, calm.presentation_events[0].find(';')));
  ASSERT_EQ(counts.presentation_events[0].rfind("glare trials: live from trial ", 0), 0u) << counts.presentation_events[0];
  // "live from trial N where the glare is L, ..." then "prepared before onset from trial M where the
  // glare is L: live, trial M - 1 dropped K of its 5 computed frame(s) (...)".
  const std::string& back = counts.presentation_events[1];
  const std::string prefix = "glare trials: frames prepared before onset from trial ";
  ASSERT_EQ(back.rfind(prefix, 0), 0u) << back;
  const int from_trial = std::stoi(back.substr(prefix.size()));
  const std::string live_from = counts.presentation_events[0].substr(std::string("glare trials: live from trial ").size());
  EXPECT_GT(from_trial, std::stoi(live_from)) << back;
  const std::string layout = live_from.substr(live_from.find(" where the glare is "), live_from.find(',') - live_from.find(" where the glare is "));
  EXPECT_NE(back.find(layout + ": live, trial " + std::to_string(from_trial - 1) + " dropped "), std::string::npos) << back;
  const std::size_t dropped_at = back.find(" dropped ") + 9;
  const int dropped = std::stoi(back.substr(dropped_at));
  EXPECT_GE(dropped, 1);
  EXPECT_LE(dropped, 5);
  EXPECT_NE(back.find(" of its 5 computed frame(s) (its frames took "), std::string::npos) << back;
  EXPECT_NE(back.find(" ms at most, against a refresh period of "), std::string::npos) << back;
}

}  // namespace
}  // namespace glarelab

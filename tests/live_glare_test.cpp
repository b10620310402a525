// Live glare: each frame computed just before its flip is the frame prepared before onset (on the
// virtual clock, without a tracker, dynamic glare is a function of time and seed), the session log
// says which presentation ran and what a glare frame cost, and with a tracker each live frame's
// gaze age at its flip is logged.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <string>

#include "cli_process.h"
#include "core/exr_io.h"
#include "runner/store/result_store.h"
#include "session_events.h"

namespace glarelab {
namespace {

struct GlareRun {
  test::RunOutput output;
  std::filesystem::path frames;
  std::filesystem::path db;
};

// The demo's first `trials` trials with [glare] presentation as given, each trial's first frame
// saved. Fewer stimulus frames keep it quick.
GlareRun run_demo(const test::ScratchDir& scratch, const std::string& presentation, int trials,
                  const std::vector<std::string>& extra = {}) {
  const auto dir = scratch.path() / presentation;
  std::filesystem::create_directories(dir);
  const auto experiment =
      test::demo_variant(dir, {{"stimulus_frames", "stimulus_frames = 3"},
                               {"grid_px", "grid_px = 128\npresentation = \"" + presentation + "\""}});
  GlareRun run{{}, dir / "frames", dir / "session.db"};
  std::vector<std::string> arguments = {"run", experiment.string(), "--display", "offscreen", "--observer", "simulated",
                                        "--db", run.db.string(), "--save-frames", run.frames.string(), "--stop-after",
                                        std::to_string(trials)};
  arguments.insert(arguments.end(), extra.begin(), extra.end());
  run.output = test::run_glarelab(arguments, dir);
  return run;
}

TEST(LiveGlare, LiveFramesEqualPreparedFramesAndTheLogSaysWhichRan) {
  const test::ScratchDir scratch;
  const int trials = 6;
  const GlareRun prepared = run_demo(scratch, "prepared", trials);
  const GlareRun live = run_demo(scratch, "live", trials);
  ASSERT_EQ(prepared.output.exit_code, 0) << prepared.output.output;
  ASSERT_EQ(live.output.exit_code, 0) << live.output.output;
  for (int trial = 0; trial < trials; ++trial) {
    char name[32];
    std::snprintf(name, sizeof name, "trial_%04d.exr", trial);
    const ImageRGBA a = read_exr((prepared.frames / name).string()).image;
    const ImageRGBA b = read_exr((live.frames / name).string()).image;
    EXPECT_EQ(a.rgba, b.rgba) << name;
  }
  // On the virtual clock the display's thread keeps its priority: no raise asked, none logged.
  EXPECT_TRUE(test::session_event_messages(prepared.db.string(), "display_priority").empty());
  const auto prepared_mode = test::session_event_messages(prepared.db.string(), "presentation_mode");
  ASSERT_EQ(prepared_mode.size(), 1u);
  EXPECT_EQ(prepared_mode[0].rfind("glare trials: frames prepared before onset ([glare] presentation = \"prepared\"); ", 0),
            0u)
      << prepared_mode[0];
  EXPECT_NE(prepared_mode[0].find(" ms per glare frame on this machine"), std::string::npos) << prepared_mode[0];
  const auto live_mode = test::session_event_messages(live.db.string(), "presentation_mode");
  ASSERT_EQ(live_mode.size(), 1u);
  EXPECT_EQ(live_mode[0].rfind("glare trials: live, each frame computed just before its flip", 0), 0u) << live_mode[0];
  // No tracker, no gaze: nothing to be late.
  EXPECT_TRUE(test::session_event_messages(live.db.string(), "gaze_latency").empty());
}

// With a tracker and a gaze window, every live frame takes the gaze of its moment: the trial's
// gaze_latency event gives its age at the flip, at least one refresh period (the tracker is read
// after each flip) and, with a 200 Hz simulated tracker, not many periods more.
TEST(LiveGlare, WithATrackerEachLiveFramesGazeAgeIsLogged) {
  const test::ScratchDir scratch;
  const auto dir = scratch.path();
  const auto experiment = test::demo_variant(
      dir, {{"stimulus_frames", "stimulus_frames = 3"},
            {"grid_px", "grid_px = 128\npresentation = \"live\"\ngaze_window_px = 128"}});
  const auto db = dir / "tracked.db";
  const auto run = test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer", "simulated",
                                       "--db", db.string(), "--tracker", "simulated", "--stop-after", "4"},
                                      dir);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto latencies = test::session_event_messages(db.string(), "gaze_latency");
  ASSERT_FALSE(latencies.empty());
  for (const std::string& message : latencies) {
    const auto at = message.find("gaze to flip mean ");
    ASSERT_NE(at, std::string::npos) << message;
    const double mean_ms = std::stod(message.substr(at + 18));
    // Trial 0's frame is prepared before the session's first flip, when the tracker is read at
    // that flip's time (t = 0 on the virtual clock): its gaze is as old as that flip, 0 ms.
    if (message.rfind("trial 0 ", 0) == 0)
      EXPECT_GE(mean_ms, 0.0) << message;
    else
      EXPECT_GT(mean_ms, 0.0) << message;
    EXPECT_LT(mean_ms, 100.0) << message;
    EXPECT_NE(message.find("live glare frame(s)"), std::string::npos) << message;
  }
  // Each live glare frame's row holds its gaze age: the flip minus the gaze sample's time, at least
  // one refresh period (samples are read after a flip) and positive; no other flip has one. The
  // session's first frame is the exception: read before any flip, at its flip's time, age 0.
  const ResultStore store(db.string());
  int aged = 0;
  for (const TrialRecord& trial : store.load_trials(store.load_sessions().at(0).id))
    for (const FrameRecord& frame : store.load_frames(trial.id)) {
      if (!frame.gaze_age_s) continue;
      ++aged;
      EXPECT_GE(frame.frame_index, 0);
      const bool first_of_session = trial.trial_index == 0 && frame.frame_index == 0;
      EXPECT_GE(*frame.gaze_age_s, first_of_session ? 0.0 : 1.0 / 60.0 - 1e-9) << "trial " << trial.trial_index;
      EXPECT_LT(*frame.gaze_age_s, 0.1);
    }
  EXPECT_GT(aged, 0);
  // The analysis reports them per session.
  const auto out = dir / "report";
  const auto analysis = test::run_glarelab({"analyze", db.string(), "--out", out.string()}, dir);
  ASSERT_EQ(analysis.exit_code, 0) << analysis.output;
  const std::string html = test::read_bytes((out / "report.html").string());
  EXPECT_NE(html.find("gaze to flip, live glare"), std::string::npos);
  EXPECT_EQ(html.find("no live glare frames"), std::string::npos);
  EXPECT_NE(test::read_bytes((out / "frames.csv").string()).find(",gaze_age_s"), std::string::npos);
}

// --clock real: an offscreen run paced by the wall clock. Each present waits for a refresh boundary,
// as a window's swap waits for the vertical blank, and the flip is stamped at that boundary: every
// flip lies on the run's refresh grid, a whole number of periods after the one before and never
// in the same period, however late a loaded host woke the process after a boundary. A flip more
// than one period after the one before is a late flip and is logged as one (a stimulus frame's
// row says dropped; a trial's onset has its late_onset event). The run takes at least its flips'
// periods of wall time, the session says it ran on the monotonic clock, and the presentation_mode
// event gives the glare cost per frame against the period. Caught: a run that does not wait for
// the boundaries (flips off the grid), flips stamped when the process woke rather than at their
// boundary (off the grid after a stall), two flips in one period, and a late flip the log does
// not call late.
TEST(LiveGlare, RealClockOffscreenRunFlipsOnTheRefreshGridAndReportsTheGlareCost) {
  const test::ScratchDir scratch;
  const auto started = std::chrono::steady_clock::now();
  const GlareRun run = run_demo(scratch, "auto", 6, {"--clock", "real"});
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  ASSERT_EQ(run.output.exit_code, 0) << run.output.output;
  const double period_s = 1.0 / 60.0;  // the demo's refresh_hz
  const ResultStore store(run.db.string());
  const SessionRecord session = store.load_sessions().at(0);
  EXPECT_EQ(session.clock, "monotonic");
  // The display's thread raised for the real clock, or why not (display_thread_priority_test.cpp).
  const auto priority = test::session_event_messages(run.db.string(), "display_priority");
  ASSERT_EQ(priority.size(), 1u);
  EXPECT_TRUE(priority[0].rfind("real-time (SCHED_RR", 0) == 0 || priority[0].rfind("normal: real-time scheduling was refused", 0) == 0)
      << priority[0];
  struct Flip {
    double flip_s;
    int trial_index, frame_index;
    bool dropped;
  };
  std::vector<Flip> flips;
  for (const TrialRecord& trial : store.load_trials(session.id))
    for (const FrameRecord& frame : store.load_frames(trial.id))
      flips.push_back({frame.flip_s, trial.trial_index, frame.frame_index, frame.dropped});
  std::sort(flips.begin(), flips.end(), [](const Flip& a, const Flip& b) { return a.flip_s < b.flip_s; });
  ASSERT_EQ(flips.size(), 18u);  // the stimulus flips, 3 a trial
  std::vector<std::string> late_onsets = test::session_event_messages(run.db.string(), "late_onset");
  std::size_t late_onsets_seen = 0;
  for (std::size_t k = 1; k < flips.size(); ++k) {
    const double periods = (flips[k].flip_s - flips[k - 1].flip_s) / period_s;
    const double whole = std::round(periods);
    ASSERT_GE(whole, 1.0) << "flips " << k - 1 << " and " << k << " in one period";
    ASSERT_NEAR(periods, whole, 1e-6) << "flip " << k << " is off the refresh grid";
    const bool late = whole >= 2.0;
    if (flips[k].frame_index > 0) {
      EXPECT_EQ(flips[k].dropped, late) << "trial " << flips[k].trial_index << " frame " << flips[k].frame_index
                                        << ": " << periods << " periods after the flip before";
    } else if (late) {
      // "trial N onset: X ms since the previous flip (cause)".
      const std::string prefix = "trial " + std::to_string(flips[k].trial_index) + " onset: ";
      const auto logged = std::find_if(late_onsets.begin(), late_onsets.end(),
                                       [&](const std::string& message) { return message.rfind(prefix, 0) == 0; });
      ASSERT_NE(logged, late_onsets.end()) << prefix << periods << " periods after the flip before, not logged";
      EXPECT_NEAR(1e-3 * std::stod(logged->substr(prefix.size())), flips[k].flip_s - flips[k - 1].flip_s, 2e-6) << *logged;
      ++late_onsets_seen;
    }
  }
  EXPECT_EQ(late_onsets_seen, late_onsets.size()) << "a late_onset event for an onset that was not late";
  EXPECT_LE(flips.back().flip_s - flips.front().flip_s, wall_s);
  const auto mode = test::session_event_messages(run.db.string(), "presentation_mode");
  // One event settling the layout; on a loaded machine a live trial may drop a frame on this real
  // clock, and then exactly one more takes the layout back to prepared frames (and only then).
  std::int64_t dropped = 0;
  for (const TrialRecord& trial : store.load_trials(session.id))
    for (const FrameRecord& frame : store.load_frames(trial.id)) dropped += frame.dropped;
  ASSERT_GE(mode.size(), 1u);
  ASSERT_LE(mode.size(), 2u);
  if (mode.size() == 2) {
    EXPECT_GT(dropped, 0) << mode[1];
    EXPECT_EQ(mode[1].rfind("glare trials: frames prepared before onset from trial ", 0), 0u) << mode[1];
  }
  EXPECT_NE(mode[0].find(" ms per glare frame on this machine"), std::string::npos) << mode[0];
  EXPECT_NE(mode[0].find("against a refresh period of 16.667 ms"), std::string::npos) << mode[0];
  // The analysis counts the dropped frames on the clock they were stamped on.
  const auto out = scratch.path() / "report";
  const auto analysis = test::run_glarelab({"analyze", run.db.string(), "--out", out.string()}, scratch.path());
  ASSERT_EQ(analysis.exit_code, 0) << analysis.output;
  EXPECT_NE(analysis.output.find(" dropped on the monotonic clock"), std::string::npos) << analysis.output;
  EXPECT_NE(test::read_bytes((out / "report.html").string()).find("<td>monotonic: the flips as they happened</td>"),
            std::string::npos);
}

// On a real clock, glare frames prepared before onset are computed during the inter-trial
// interval, which is shortened by the time they took: the time from a trial's last stimulus flip
// to the next trial's first is the same whether the next trial's glare is prepared, static or
// absent (within the pacing's few periods), not longer by the preparation (20 frames of dynamic
// glare: about a dozen periods here). The host may stall (a loaded machine stops the process for
// 100 ms and more now and then); every flip that came late is logged as late (frames.dropped, more
// than 1.5 periods after the flip before it; a trial's onset, a late_onset event with the likely
// cause), so what a stall adds is read from the log: each gap less the lateness of the late flips
// within it must stay within the pacing's few periods of the others. Preparation the interval did
// not absorb would stay in the gap unexplained: the flip that follows the preparation is not a late
// flip, or the onset it delays is logged late with glare preparation as the session's work since
// the flip before, which is not taken out unless it was the logged wait for the worker. The
// interval is 1.5 s, several times what the preparation takes here on an idle machine. A trial
// prepared ahead on a worker beside the one before logs how long its onset waited for that worker
// (trial_preparation): on a loaded machine (load 15 on two cores) 20 dynamic frames took the worker
// 2 s and more, and the onset waited for them; that wait is the log's too, so it is taken out of
// the gap as the late flips' lateness is.
TEST(LiveGlare, OnARealClockPreparedGlareTakesItsTimeFromTheInterTrialInterval) {
  const test::ScratchDir scratch;
  const auto dir = scratch.path();
  const auto experiment = test::demo_variant(
      dir, {{"stimulus_frames", "stimulus_frames = 20"},
            // The wave-optics eye alone, whose preparation the 1.5 s interval is sized for.
            {"grid_px", "grid_px = 256\npresentation = \"prepared\"\nmodel = \"ritschel\""},
            {"dynamic", "dynamic = 0.25\n\n[presentation]\nisi_duration_s = 1.5"}});
  const auto db = dir / "paced.db";
  const auto run = test::run_glarelab({"run", experiment.string(), "--display", "offscreen", "--observer", "simulated",
                                       "--db", db.string(), "--clock", "real", "--stop-after", "6"},
                                      dir);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const double period_s = 1.0 / 60.0;
  const ResultStore store(db.string());
  const std::vector<TrialRecord> trials = store.load_trials(store.load_sessions().at(0).id);
  ASSERT_EQ(trials.size(), 6u);
  // "trial N: frames prepared ahead beside trial N-1 (...); the onset waited W ms for them; ...".
  std::vector<double> onset_wait_s(trials.size(), 0.0);
  for (const std::string& message : test::session_event_messages(db.string(), "trial_preparation")) {
    const std::string waited = "the onset waited ";
    const auto at = message.find(waited);
    if (at == std::string::npos) continue;
    const auto trial = static_cast<std::size_t>(std::stoi(message.substr(std::string("trial ").size())));
    ASSERT_LT(trial, trials.size()) << message;
    onset_wait_s[trial] = 1e-3 * std::stod(message.substr(at + waited.size()));
  }
  // "trial N onset: X ms since the previous flip (cause); the session's work since that flip: glare
  // preparation G ms, ...": a late onset's lateness is explained by the log but for the glare
  // preparation in it that was not the logged wait for the worker (preparation the interval did
  // not absorb).
  std::vector<double> onset_explained_s(trials.size(), 0.0);
  for (const std::string& message : test::session_event_messages(db.string(), "late_onset")) {
    const auto trial = static_cast<std::size_t>(std::stoi(message.substr(std::string("trial ").size())));
    ASSERT_LT(trial, trials.size()) << message;
    const double lateness_s = 1e-3 * std::stod(message.substr(message.find(" onset: ") + 8)) - period_s;
    const std::string glare = "glare preparation ";
    const auto at = message.find(glare, message.find("work since that flip"));
    ASSERT_NE(at, std::string::npos) << message;
    const double glare_s = 1e-3 * std::stod(message.substr(at + glare.size()));
    onset_explained_s[trial] = lateness_s - std::max(0.0, glare_s - onset_wait_s[trial]);
  }
  std::vector<double> gaps_s, unexplained_s;
  std::string described;
  bool dynamic_seen = false;
  for (std::size_t t = 1; t < trials.size(); ++t) {
    // Stimulus flips only (frame_index >= 0; the inter-trial flips are numbered -1, -2, ...).
    const std::vector<FrameRecord> before = store.load_frames(trials[t - 1].id);
    const std::vector<FrameRecord> after = store.load_frames(trials[t].id);
    double last_s = -1e9, first_s = 1e9;
    for (const FrameRecord& frame : before)
      if (frame.frame_index >= 0) last_s = std::max(last_s, frame.flip_s);
    for (const FrameRecord& frame : after)
      if (frame.frame_index >= 0) first_s = std::min(first_s, frame.flip_s);
    ASSERT_GT(last_s, -1e9);
    ASSERT_LT(first_s, 1e9);
    // The flips between (the answer, feedback, inter-trial and fixation flips, and the first
    // stimulus flip), in flip order: a late one adds its interval's excess over one period.
    std::vector<FrameRecord> between;
    for (const FrameRecord& frame : before)
      if (frame.flip_s > last_s) between.push_back(frame);
    for (const FrameRecord& frame : after)
      if (frame.flip_s <= first_s) between.push_back(frame);
    std::sort(between.begin(), between.end(),
              [](const FrameRecord& a, const FrameRecord& b) { return a.flip_s < b.flip_s; });
    double late_excess_s = 0.0, previous_s = last_s;
    int late_flips = 0;
    for (const FrameRecord& frame : between) {
      if (frame.dropped) late_excess_s += frame.flip_s - previous_s - period_s, ++late_flips;
      previous_s = frame.flip_s;
    }
    gaps_s.push_back(first_s - last_s);
    unexplained_s.push_back(gaps_s.back() - late_excess_s - onset_explained_s[t]);
    dynamic_seen = dynamic_seen || trials[t].condition.find("\"glare_a\":\"dynamic\"") != std::string::npos;
    described += " " + std::to_string(1000.0 * gaps_s.back()) + " ms, " + std::to_string(late_flips) +
                 " late flip(s) adding " + std::to_string(1000.0 * late_excess_s) + " ms, onset waited " +
                 std::to_string(1000.0 * onset_wait_s[t]) + " ms, onset lateness the log explains " +
                 std::to_string(1000.0 * onset_explained_s[t]) + " ms (" +
                 trials[t].condition.substr(0, 24) + ");";
  }
  ASSERT_TRUE(dynamic_seen) << described;
  EXPECT_GE(*std::min_element(gaps_s.begin(), gaps_s.end()), 1.5);  // the inter-trial interval itself
  const auto [shortest, longest] = std::minmax_element(unexplained_s.begin(), unexplained_s.end());
  EXPECT_LE(*longest - *shortest, 4.0 * period_s) << "gaps:" << described;
}

// A virtual clock cannot stamp a window's flips: refused as bad input before anything opens.
TEST(LiveGlare, VirtualClockInAWindowIsRefusedNamingTheFlag) {
  const test::ScratchDir scratch;
  const auto db = scratch.path() / "never.db";
  const auto run = test::run_glarelab({"run", (std::filesystem::path(GLARELAB_SOURCE_DIR) / "examples" / "demo.toml").string(), "--display",
                                       "window", "--clock", "virtual", "--db", db.string()},
                                      scratch.path());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("--clock"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("a window"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(db));
}

}  // namespace
}  // namespace glarelab

// Trials prepared ahead (runner/session/trial_ahead.cpp, docs/TIMING.md "Trials prepared ahead"):
// the procedure's peeks at the following trials are the trials it then hands out, in every fixed design
// of examples/; a session prepares each known trial's glare beside the one before, so its onset
// computes none, and the frames it shows are the ones preparing them at the trial makes. What is
// asserted is what the session logged and saved, never how the host kept time.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_process.h"
#include "core/exr_io.h"
#include "protocols/experiment.h"
#include "protocols/fixed_design_procedure.h"
#include "protocols/procedure.h"
#include "runner/session/frame_timing.h"
#include "runner/store/result_store.h"
#include "scratch_dir.h"
#include "session_events.h"
#include "stimuli/scene_library.h"

namespace glarelab {
namespace {

// Every field a trial shows or scores by, compared one by one (the session's own comparison looks
// at fewer: this is the stricter reference).
void expect_same_plan(const TrialPlan& peeked, const TrialPlan& shown, const std::string& where) {
  EXPECT_EQ(peeked.trial_index, shown.trial_index) << where;
  EXPECT_EQ(peeked.block, shown.block) << where;
  EXPECT_EQ(peeked.block_name, shown.block_name) << where;
  EXPECT_EQ(peeked.screen_text, shown.screen_text) << where;
  EXPECT_EQ(peeked.procedure, shown.procedure) << where;
  EXPECT_EQ(peeked.condition_name, shown.condition_name) << where;
  EXPECT_EQ(peeked.condition_json, shown.condition_json) << where;
  EXPECT_EQ(peeked.positions, shown.positions) << where;
  EXPECT_EQ(peeked.scenes, shown.scenes) << where;
  EXPECT_EQ(peeked.real_stimulus, shown.real_stimulus) << where;
  EXPECT_EQ(peeked.position_conditions, shown.position_conditions) << where;
  EXPECT_EQ(peeked.position_glare, shown.position_glare) << where;
  EXPECT_EQ(peeked.glare_keeps_peak, shown.glare_keeps_peak) << where;
  EXPECT_EQ(peeked.source_luminance_cd_m2, shown.source_luminance_cd_m2) << where;
  EXPECT_EQ(peeked.scene_scale, shown.scene_scale) << where;
  EXPECT_EQ(peeked.adjustment_start_cd_m2, shown.adjustment_start_cd_m2) << where;
  EXPECT_EQ(peeked.allowed_responses, shown.allowed_responses) << where;
  EXPECT_EQ(peeked.correct_response, shown.correct_response) << where;
  EXPECT_EQ(peeked.question, shown.question) << where;
  EXPECT_EQ(peeked.stimulus_frames, shown.stimulus_frames) << where;
}

// An answer the plan takes (adjustment plans allow any text: its two spot settings).
Response answer_for(const TrialPlan& plan) {
  return Response{plan.allowed_responses.empty() ? std::string("100 100") : plan.allowed_responses.front(), 1.0};
}

TEST(TrialAhead, PeekIsTheTrialShownNextInEveryFixedDesignExample) {
  int fixed_designs = 0, peeks = 0, later_peeks = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(GLARELAB_SOURCE_DIR) + "/examples")) {
    if (entry.path().extension() != ".toml") continue;
    const std::string name = entry.path().filename().string();
    Experiment experiment;
    try {
      experiment = load_experiment(entry.path().string());
    } catch (const std::exception&) {
      continue;  // not an experiment file (an eye or display file beside them)
    }
    const SceneLibrary scenes(experiment.scenes, experiment.display);
    const auto procedure = make_procedure(experiment, scenes.peak_luminances_cd_m2());
    if (dynamic_cast<const FixedDesignProcedure*>(procedure.get()) == nullptr) {
      // Adaptive designs place the next trial by the answer: the peek says it is not known.
      EXPECT_FALSE(procedure->peek_following_trial().has_value()) << name;
      EXPECT_FALSE(procedure->peek_following_trial(1).has_value()) << name;
      continue;
    }
    ++fixed_designs;
    // Before each trial: the peeks at the trial after it and at the one after that; then the
    // trials as the design hands them out, each answered.
    std::vector<std::optional<TrialPlan>> peeked_next, peeked_later;
    std::vector<TrialPlan> shown;
    while (!procedure->finished()) {
      peeked_next.push_back(procedure->peek_following_trial());
      peeked_later.push_back(procedure->peek_following_trial(1));
      shown.push_back(procedure->next_trial());
      procedure->record_response(shown.back(), answer_for(shown.back()));
    }
    for (std::size_t t = 0; t < shown.size(); ++t) {
      const std::string at = name + " before trial " + std::to_string(t);
      if (t + 1 < shown.size()) {
        ASSERT_TRUE(peeked_next[t].has_value()) << at;
        expect_same_plan(*peeked_next[t], shown[t + 1], at);
        ++peeks;
      } else {
        EXPECT_FALSE(peeked_next[t].has_value()) << at << ": a peek after the last trial";
      }
      if (t + 2 < shown.size()) {
        ASSERT_TRUE(peeked_later[t].has_value()) << at;
        expect_same_plan(*peeked_later[t], shown[t + 2], at + ", one further");
        ++later_peeks;
      } else {
        EXPECT_FALSE(peeked_later[t].has_value()) << at << ": a peek one further, past the last trial";
      }
    }
  }
  EXPECT_GE(fixed_designs, 5) << "the examples hold forced-choice, rating and adjustment designs";
  EXPECT_GT(peeks, 100);
  EXPECT_GT(later_peeks, 100);
}

TEST(TrialAhead, AnAnswerThatDoesNotAdvanceShowsTheSameTrialNotThePeekedOne) {
  const Experiment experiment = load_experiment(std::string(GLARELAB_SOURCE_DIR) + "/examples/demo.toml");
  const SceneLibrary scenes(experiment.scenes, experiment.display);
  const auto procedure = make_procedure(experiment, scenes.peak_luminances_cd_m2());
  const std::optional<TrialPlan> peeked = procedure->peek_following_trial();
  ASSERT_TRUE(peeked.has_value());
  const TrialPlan plan = procedure->next_trial();
  procedure->record_response(plan, Response{"abort", std::nullopt});
  const TrialPlan again = procedure->next_trial();
  EXPECT_EQ(again.trial_index, plan.trial_index);
  EXPECT_NE(again.trial_index, peeked->trial_index);
  // Peeking does not advance the design.
  EXPECT_EQ(procedure->peek_following_trial()->trial_index, peeked->trial_index);
}

// The trial's commit to the database is the session's own work: an onset it delays is late for
// recording the trial, not for a host stall.
TEST(TrialAhead, AnOnsetDelayedByRecordingTheTrialNamesThatCause) {
  FrameTimingMonitor monitor(60.0);
  const double period_s = 1.0 / 60.0;
  monitor.on_flip(0.0, 0, 0);
  monitor.on_flip(period_s, 0, 1);
  monitor.add_work(FlipWork::recording, 0.030);  // 30 ms of a 40 ms delay
  monitor.add_work(FlipWork::drawing, 0.002);
  monitor.on_flip(2 * period_s + 0.040, 1, 0);
  monitor.add_work(FlipWork::recording, 0.005);  // 5 ms of a 40 ms delay: the host stalled
  monitor.on_flip(3 * period_s + 0.080, 2, 0);
  const FrameTimingSummary summary = monitor.summary();
  EXPECT_EQ(summary.late_onsets, 2);
  EXPECT_EQ(summary.late_onsets_by_cause[static_cast<int>(FlipWork::recording)], 1);
  EXPECT_EQ(summary.late_onsets_by_cause[kHostStallCause], 1);
  EXPECT_NE(summary.describe().find("late onsets 2 (recording the trial 1, host stall 1)"), std::string::npos)
      << summary.describe();
}

std::vector<std::string> run_and_read_preparation(const test::ScratchDir& dir, const std::string& experiment,
                                                  const std::string& db, const std::string& frames_dir,
                                                  const std::vector<std::string>& extra) {
  std::vector<std::string> arguments = {"run",  experiment, "--display", "offscreen", "--observer", "simulated",
                                        "--db", db,         "--seed", "3", "--save-frames", frames_dir};
  arguments.insert(arguments.end(), extra.begin(), extra.end());
  std::filesystem::create_directories(frames_dir);
  const auto run = test::run_glarelab(arguments, dir.path());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  return test::session_event_messages(db, "trial_preparation");
}

TEST(TrialAhead, EveryKnownTrialIsPreparedAheadAndItsFramesAreThoseMadeAtTheTrial) {
  const test::ScratchDir dir;
  const std::string experiment = test::small_dynamic_demo(dir.path(), "").string();
  const std::string whole_db = dir.file("whole.db");
  const std::vector<std::string> whole = run_and_read_preparation(dir, experiment, whole_db, dir.file("whole"), {});
  // Ten trials (five rows, both sides), every one with dynamic glare: the first prepared at the
  // trial, the second beside it, each later one beside the trial two before (two trials are
  // prepared ahead, SessionLoop::kTrialsAhead), with no glare frame left for its onset. On the
  // virtual clock a trial whose frames were timed for other flips than it shows is prepared again
  // at the trial: each is timed where the trials before it end.
  ASSERT_EQ(whole.size(), 10u);
  EXPECT_NE(whole[0].find("trial 0: frames prepared at the trial, not ahead: the first trial of the run"),
            std::string::npos)
      << whole[0];
  EXPECT_EQ(whole[0].find("glare frames computed on the display's thread for the onset: 0"), std::string::npos) << whole[0];
  for (std::size_t t = 1; t < whole.size(); ++t) {
    EXPECT_NE(whole[t].find("trial " + std::to_string(t) + ": frames prepared ahead beside trial " +
                            std::to_string(t < 2 ? 0 : t - 2) + " (2 glare frame(s) on a worker"),
              std::string::npos)
        << whole[t];
    EXPECT_NE(whole[t].find("glare frames computed on the display's thread for the onset: 0"), std::string::npos) << whole[t];
    // The display's thread only lays the trial out: its scenes are composed on the worker, and
    // nothing is written to the stimulus framebuffer for it before its onset (a count, not a time).
    EXPECT_NE(whole[t].find("its scenes composed there on the CPU"), std::string::npos) << whole[t];
    EXPECT_NE(whole[t].find(" 0 write(s) to the stimulus framebuffer"), std::string::npos) << whole[t];
  }

  // glarelab render computes its trial's frame at the trial (a preview is never prepared ahead),
  // with the eye's history of the trials before carried over: for each condition, the session's
  // first trial of it, prepared ahead from trial 1 on, saved the same frame bit for bit.
  const ResultStore store(whole_db);
  const std::vector<TrialRecord> trials = store.load_trials(store.load_sessions().at(0).id);
  // Each trial's commit went beside the next trial's start, on the committer's own connection, and
  // every answered trial is in the database with its flips.
  const std::vector<std::string> commits = test::session_event_messages(whole_db, "trial_commits");
  ASSERT_EQ(commits.size(), 1u);
  EXPECT_EQ(commits[0].rfind("10 trial(s) committed on a connection of their own beside the next trial's start", 0), 0u)
      << commits[0];
  EXPECT_NE(commits[0].find("; 0 committed at once"), std::string::npos) << commits[0];
  EXPECT_EQ(trials.size(), 10u);
  EXPECT_EQ(test::session_event_messages(whole_db, "trial_phases").size(), 10u);
  int compared_ahead = 0;
  for (const std::string condition : {"ratio_1.05", "ratio_1.15", "ratio_1.30", "ratio_1.60", "ratio_2.00"}) {
    int trial = -1;
    for (const TrialRecord& record : trials)
      if (trial < 0 && record.condition.find("\"name\":\"" + condition + "\"") != std::string::npos)
        trial = record.trial_index;
    ASSERT_GE(trial, 0) << condition;
    const std::string out = dir.file(condition + ".exr");
    const auto render = test::run_glarelab({"render", experiment, "--condition", condition, "--seed", "3", "--out", out},
                                           dir.path());
    ASSERT_EQ(render.exit_code, 0) << render.output;
    char name[32];
    std::snprintf(name, sizeof name, "trial_%04d.exr", trial);
    const ImageRGBA shown = read_exr(dir.file("whole") + "/" + name).image;
    const ImageRGBA rendered = read_exr(out).image;
    ASSERT_EQ(shown.rgba.size(), rendered.rgba.size()) << name;
    EXPECT_EQ(shown.rgba, rendered.rgba) << name << " (" << condition << "): a frame prepared ahead differs from "
                                         << "the one computed at the trial";
    compared_ahead += trial > 0 ? 1 : 0;
  }
  EXPECT_GE(compared_ahead, 3);
}

// An abort while two trials are prepared ahead (the second's worker waiting for the first's) ends
// the session at once: both workers are stopped, the answered trials are kept, and the resumed
// session, whose first trial is prepared at the trial, prepares the two after it beside it again.
TEST(TrialAhead, AnAbortStopsBothTrialsPreparedAheadAndTheResumedRunPreparesTwoAheadAgain) {
  const test::ScratchDir dir;
  const std::string experiment = test::small_dynamic_demo(dir.path(), "").string();
  // Entry k answers trial k; the resumed run shows trial 2 again and reads entry 2 again, so the
  // second script holds an answer there.
  test::write_bytes(dir.file("aborting.txt"), "left\nleft\nabort\n");
  test::write_bytes(dir.file("answers.txt"), "left\nleft\nleft\nleft\nleft\nleft\nleft\nleft\nleft\nleft\n");
  const std::string db = dir.file("aborted.db");
  const auto aborted = test::run_glarelab({"run", experiment, "--display", "offscreen", "--observer",
                                           "script:" + dir.file("aborting.txt"), "--db", db, "--seed", "3"},
                                          dir.path());
  EXPECT_EQ(aborted.exit_code, 130) << aborted.output;
  EXPECT_NE(aborted.output.find("aborted"), std::string::npos) << aborted.output;
  {
    const ResultStore store(db);
    EXPECT_EQ(store.load_trials(store.load_sessions().at(0).id).size(), 2u);
  }
  const auto resumed = test::run_glarelab({"run", experiment, "--display", "offscreen", "--observer",
                                           "script:" + dir.file("answers.txt"), "--db", db, "--resume", "1"},
                                          dir.path());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  const ResultStore store(db);
  ASSERT_EQ(store.load_trials(store.load_sessions().at(0).id).size(), 10u);
  const std::vector<std::string> preparation = test::session_event_messages(db, "trial_preparation");
  // Trials 0 to 2 in the aborted run (trial 2 shown, aborted at its answer: its event is written
  // when the session ends), then 2 to 9 in the resumed one.
  ASSERT_EQ(preparation.size(), 11u);
  EXPECT_NE(preparation[1].find("trial 1: frames prepared ahead beside trial 0"), std::string::npos) << preparation[1];
  EXPECT_NE(preparation[2].find("trial 2: frames prepared ahead beside trial 0"), std::string::npos) << preparation[2];
  EXPECT_NE(preparation[3].find("trial 2: frames prepared at the trial, not ahead: the first trial of the run"),
            std::string::npos)
      << preparation[3];
  for (int t = 3; t < 10; ++t)
    EXPECT_NE(preparation[static_cast<std::size_t>(t + 1)].find("trial " + std::to_string(t) +
                                                                ": frames prepared ahead beside trial " +
                                                                std::to_string(t == 3 ? 2 : t - 2)),
              std::string::npos)
        << preparation[static_cast<std::size_t>(t + 1)];
}

}  // namespace
}  // namespace glarelab

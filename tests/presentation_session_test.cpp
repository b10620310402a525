// Whole offscreen sessions with [presentation] phases on the virtual clock (flip k at k / 60 s):
// exact flip counts of screens, fixation, intervals and feedback in `frames` and in the session
// log; sequential two-interval 2-AFC with the simulated and a scripted observer; the response
// window; rounding of durations given in seconds.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <map>

#include "cli_process.h"
#include "runner/store/result_store.h"
#include "session_events.h"

namespace glarelab {
namespace {

using test::run_glarelab;
using test::ScratchDir;

struct StudySetup {
  std::string procedure = "layout = \"sequential\"\nstimulus_frames = 4\nrepetitions = 2";
  std::string rows = "{ name = \"far\", scene_a = \"lamp_100\", scene_b = \"lamp_200\" }";
  std::string presentation;
  std::string observer = "threshold_log10 = 0.05";
};

std::string write_experiment(const ScratchDir& scratch, const StudySetup& setup) {
  const std::string scenes = std::string(GLARELAB_SOURCE_DIR) + "/examples/scenes/";
  return scratch.write(
      "experiment.toml",
      "[experiment]\nname = \"presentation\"\nseed = 5\n\n"
      "[display]\nwidth_px = 256\nheight_px = 128\nrefresh_hz = 60.0\n\n"
      "[scenes]\n"
      "lamp_100 = { file = \"" + scenes + "lamp_100.exr\" }\n"
      "lamp_105 = { file = \"" + scenes + "lamp_105.exr\" }\n"
      "lamp_200 = { file = \"" + scenes + "lamp_200.exr\" }\n\n"
      "[procedure]\ntype = \"forced_choice\"\n" + setup.procedure + "\n\n"
      "[conditions]\nrows = [ " + setup.rows + " ]\n\n"
      "[observer.simulated]\n" + setup.observer + "\n\n"
      "[presentation]\n" + setup.presentation + "\n");
}

std::vector<std::string> events(const ResultStore& store, const std::string& kind) {
  return test::session_event_messages(store, kind);
}

std::string frame_indices(const std::vector<FrameRecord>& frames) {
  std::string text;
  for (const FrameRecord& frame : frames) text += (text.empty() ? "" : ",") + std::to_string(frame.frame_index);
  return text;
}

// Trial rows and their frames without the wall clock, for comparing runs.
std::vector<std::string> comparable_trials(const ResultStore& store, std::int64_t session_id) {
  std::vector<std::string> rows;
  for (const TrialRecord& trial : store.load_trials(session_id)) {
    std::ostringstream row;
    row.precision(17);
    row << trial.trial_index << "|" << trial.condition << "|" << trial.response << "|"
        << (trial.correct ? std::to_string(*trial.correct) : "NULL") << "|" << trial.onset_s;
    for (const FrameRecord& frame : store.load_frames(trial.id))
      row << "|" << frame.frame_index << ":" << frame.scheduled_s << ":" << frame.flip_s << ":" << frame.dropped;
    rows.push_back(row.str());
  }
  return rows;
}

const std::string kPhases =
    "instructions = \"Which interval holds the brighter light? Press 1 or 2.\"\n"
    "screen_min_frames = 6\nfixation_frames = 3\nisi_frames = 2\nbreak_every_trials = 2\n"
    "feedback = \"text\"\nfeedback_frames = 5\n";

TEST(PresentationSession, EveryFlipOfEveryPhaseIsCountedAndStamped) {
  const ScratchDir scratch;
  StudySetup setup;
  setup.presentation = kPhases;
  const std::string db = scratch.file("p.db");
  const auto result = run_glarelab({"run", write_experiment(scratch, setup), "--display", "offscreen", "--observer",
                                    "simulated", "--db", db},
                                   scratch.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const ResultStore store(db);
  const auto trials = store.load_trials(1);
  ASSERT_EQ(trials.size(), 4u);  // 1 row x 2 repetitions x 2 orders

  // Hand-counted flips per trial: instructions 6 (trial 0) or inter-trial 2, a break screen of 6
  // before trial 2, fixation 3, interval 1 4, inter-stimulus 2, interval 2 4, feedback 5 (every
  // trial is scored: 100 against 200 cd/m2).
  const std::vector<std::string> expected_indices = {
      "-1,-2,-3,-4,-5,-6,-7,-8,-9,0,1,2,3,-10,-11,4,5,6,7,-12,-13,-14,-15,-16",
      "-1,-2,-3,-4,-5,0,1,2,3,-6,-7,4,5,6,7,-8,-9,-10,-11,-12",
      "-1,-2,-3,-4,-5,-6,-7,-8,-9,-10,-11,0,1,2,3,-12,-13,4,5,6,7,-14,-15,-16,-17,-18",
      "-1,-2,-3,-4,-5,0,1,2,3,-6,-7,4,5,6,7,-8,-9,-10,-11,-12"};
  const std::vector<int> onset_flips = {9, 24 + 2 + 3, 44 + 2 + 6 + 3, 70 + 2 + 3};
  int flip = 0;
  for (std::size_t t = 0; t < trials.size(); ++t) {
    const auto frames = store.load_frames(trials[t].id);
    EXPECT_EQ(frame_indices(frames), expected_indices[t]) << "trial " << t;
    EXPECT_NEAR(trials[t].onset_s, onset_flips[t] / 60.0, 1e-12) << "trial " << t;
    for (const FrameRecord& frame : frames) {
      // The virtual clock: one flip after another, no gaps anywhere in the session.
      EXPECT_NEAR(frame.flip_s, flip++ / 60.0, 1e-12);
      EXPECT_FALSE(frame.dropped);
      if (frame.frame_index >= 0) {
        EXPECT_NEAR(frame.scheduled_s, frame.flip_s, 1e-12);
      }
    }
    EXPECT_TRUE(trials[t].correct.has_value());
  }
  EXPECT_EQ(store.frame_count(1), flip);

  EXPECT_EQ(events(store, "trial_phases"),
            (std::vector<std::string>{
                "trial 0: screen 6, fixation 3, interval 1 4 (frames 0-3), inter-stimulus 2, interval 2 4 (frames 4-7), "
                "feedback 5 flips",
                "trial 1: inter-trial 2, fixation 3, interval 1 4 (frames 0-3), inter-stimulus 2, interval 2 4 (frames "
                "4-7), feedback 5 flips",
                "trial 2: inter-trial 2, screen 6, fixation 3, interval 1 4 (frames 0-3), inter-stimulus 2, interval 2 "
                "4 (frames 4-7), feedback 5 flips",
                "trial 3: inter-trial 2, fixation 3, interval 1 4 (frames 0-3), inter-stimulus 2, interval 2 4 (frames "
                "4-7), feedback 5 flips"}));
  EXPECT_EQ(events(store, "screen"),
            (std::vector<std::string>{
                "trial 0, instructions: 'Which interval holds the brighter light? Press 1 ...' shown 6 flips (0.1 s)",
                "trial 2, break: 'Take a short break. Press Space to continue.' shown 6 flips (0.1 s)"}));
  // The summary counts stimulus frames only.
  EXPECT_NE(result.output.find("32 frames, 0 dropped"), std::string::npos) << result.output;
}

TEST(PresentationSession, StopAndResumeFlipsExactlyAsAnUninterruptedRun) {
  const ScratchDir scratch;
  StudySetup setup;
  setup.presentation = kPhases;
  const std::string experiment = write_experiment(scratch, setup);
  const std::vector<std::string> common = {"run", experiment, "--display", "offscreen", "--observer", "simulated"};
  auto args = [&](std::vector<std::string> extra) {
    std::vector<std::string> all = common;
    all.insert(all.end(), extra.begin(), extra.end());
    return all;
  };
  ASSERT_EQ(run_glarelab(args({"--db", scratch.file("full.db")}), scratch.path()).exit_code, 0);
  ASSERT_EQ(run_glarelab(args({"--db", scratch.file("cut.db"), "--stop-after", "3"}), scratch.path()).exit_code, 0);
  const auto resumed = run_glarelab(args({"--db", scratch.file("cut.db"), "--resume", "1"}), scratch.path());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(comparable_trials(ResultStore(scratch.file("full.db")), 1),
            comparable_trials(ResultStore(scratch.file("cut.db")), 1));
}

TEST(PresentationSession, SequentialCorrectRateGrowsWithTheLuminanceDifference) {
  const ScratchDir scratch;
  StudySetup setup;
  setup.procedure = "layout = \"sequential\"\nstimulus_frames = 1\nrepetitions = 15";
  setup.rows = "{ name = \"near\", scene_a = \"lamp_100\", scene_b = \"lamp_105\" }, "
               "{ name = \"far\", scene_a = \"lamp_100\", scene_b = \"lamp_200\" }";
  setup.presentation = "isi_frames = 1\nquestion_above_stimuli = false";
  const std::string db = scratch.file("s.db");
  const auto result = run_glarelab({"run", write_experiment(scratch, setup), "--display", "offscreen", "--observer",
                                    "simulated", "--db", db},
                                   scratch.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const ResultStore store(db);
  std::map<std::string, std::pair<int, int>> tally;  // row -> (correct, trials)
  int first_answers = 0;
  for (const TrialRecord& trial : store.load_trials(1)) {
    const std::string row = trial.condition.find("\"near\"") != std::string::npos ? "near" : "far";
    ASSERT_TRUE(trial.response == "first" || trial.response == "second") << trial.response;
    ASSERT_TRUE(trial.correct.has_value());
    // The brighter source is lamp_105 or lamp_200, in the interval the condition names.
    const std::string brighter = row == "near" ? "lamp_105" : "lamp_200";
    const bool brighter_first = trial.condition.find("\"first\":\"" + brighter + "\"") != std::string::npos;
    EXPECT_EQ(*trial.correct, (trial.response == "first") == brighter_first ? 1 : 0) << trial.condition;
    tally[row].first += *trial.correct;
    ++tally[row].second;
    first_answers += trial.response == "first" ? 1 : 0;
    EXPECT_EQ(store.load_frames(trial.id).size(), trial.trial_index == 0 ? 3u : 4u);  // [inter-trial,] 1, isi, 1
  }
  ASSERT_EQ(tally["near"].second, 30);
  ASSERT_EQ(tally["far"].second, 30);
  // Weibull observer (threshold 0.05, slope 3.5, lapse 0.02): p = 0.52 at log10(1.05) = 0.021 and
  // 0.98 at log10(2) = 0.30.
  const double near = tally["near"].first / 30.0;
  const double far = tally["far"].first / 30.0;
  EXPECT_GE(far, 0.9);
  EXPECT_LE(near, 0.75);
  EXPECT_GT(far - near, 0.25);
  EXPECT_GT(first_answers, 15) << "both intervals get answered";
  EXPECT_LT(first_answers, 45);
}

TEST(PresentationSession, ScriptAnswersSequentialTrialsIncludingTimeouts) {
  const ScratchDir scratch;
  StudySetup setup;
  setup.procedure = "layout = \"sequential\"\nstimulus_frames = 2\nrepetitions = 3";
  setup.presentation = "response_window_s = 2.0\nfeedback = \"text\"\nfeedback_frames = 2";
  test::write_bytes(scratch.file("answers.txt"), "first\nsecond\n1\n0\ntimeout\n1\n");
  const std::string db = scratch.file("script.db");
  const auto result = run_glarelab({"run", write_experiment(scratch, setup), "--display", "offscreen", "--observer",
                                    "script:" + scratch.file("answers.txt"), "--db", db},
                                   scratch.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const ResultStore store(db);
  const auto trials = store.load_trials(1);
  ASSERT_EQ(trials.size(), 6u);
  const std::vector<std::string> script = {"first", "second", "1", "0", "timeout", "1"};
  for (std::size_t t = 0; t < trials.size(); ++t) {
    const bool brighter_first = trials[t].condition.find("\"first\":\"lamp_200\"") != std::string::npos;
    const std::string right = brighter_first ? "first" : "second";
    if (script[t] == "timeout") {
      EXPECT_EQ(trials[t].response, "timeout");
      EXPECT_FALSE(trials[t].correct.has_value()) << "a timeout is never scored";
    } else if (script[t] == "1" || script[t] == "0") {
      EXPECT_EQ(trials[t].response, script[t] == "1" ? right : (brighter_first ? "second" : "first"));
      EXPECT_EQ(trials[t].correct, script[t] == "1" ? 1 : 0);
    } else {
      EXPECT_EQ(trials[t].response, script[t]);
      EXPECT_EQ(trials[t].correct, script[t] == right ? 1 : 0);
    }
    // Feedback (correct, wrong or the timeout text) follows every trial: 2 flips.
    const auto frames = store.load_frames(trials[t].id);
    EXPECT_EQ(frames.back().frame_index, -2);
  }
  for (const std::string& phases : events(store, "trial_phases"))
    EXPECT_NE(phases.find("feedback 2 flips"), std::string::npos) << phases;

  // Without a response window a script cannot time out: refused at its line.
  StudySetup unlimited = setup;
  unlimited.presentation = "";
  const auto refused = run_glarelab({"run", write_experiment(scratch, unlimited), "--display", "offscreen",
                                     "--observer", "script:" + scratch.file("answers.txt"), "--db",
                                     scratch.file("refused.db")},
                                    scratch.path());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find(scratch.file("answers.txt") + ":5:1"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("response 'timeout' is not allowed"), std::string::npos) << refused.output;
}

TEST(PresentationSession, SlowAnswersTimeOutAndAreNeverScored) {
  const ScratchDir scratch;
  StudySetup setup;
  setup.procedure = "stimulus_frames = 2\nrepetitions = 2";
  setup.presentation = "response_window_s = 1.0\nfeedback = \"text\"\nfeedback_frames = 3";
  // Median response time 10 s (lognormal, sigma 0.25 of ln t): never within 1 s.
  setup.observer = "response_time_median_s = 10.0";
  const std::string db = scratch.file("slow.db");
  ASSERT_EQ(run_glarelab({"run", write_experiment(scratch, setup), "--display", "offscreen", "--observer", "simulated",
                          "--db", db},
                         scratch.path())
                .exit_code,
            0);
  {
    const ResultStore store(db);
    const auto trials = store.load_trials(1);
    ASSERT_EQ(trials.size(), 4u);
    for (const TrialRecord& trial : trials) {
      EXPECT_EQ(trial.response, "timeout");
      EXPECT_FALSE(trial.correct.has_value());
      EXPECT_FALSE(trial.response_time_s.has_value());
      EXPECT_EQ(store.load_frames(trial.id).back().frame_index, -3) << "the timeout text is shown for 3 flips";
    }
  }
  // Median 0.3 s: every answer is in time (ln(1 / 0.3) / 0.25 = 4.8 standard deviations).
  setup.observer = "response_time_median_s = 0.3";
  const std::string fast_db = scratch.file("fast.db");
  ASSERT_EQ(run_glarelab({"run", write_experiment(scratch, setup), "--display", "offscreen", "--observer", "simulated",
                          "--db", fast_db},
                         scratch.path())
                .exit_code,
            0);
  const ResultStore fast(fast_db);
  for (const TrialRecord& trial : fast.load_trials(1)) {
    EXPECT_TRUE(trial.response == "left" || trial.response == "right") << trial.response;
    EXPECT_TRUE(trial.correct.has_value());
  }
}

TEST(PresentationSession, DurationsInSecondsAreRoundedAndLogged) {
  const ScratchDir scratch;
  StudySetup setup;
  setup.procedure = "stimulus_duration_s = 0.05\nrepetitions = 1\ncounterbalance_sides = false";
  setup.presentation = "fixation_duration_s = 0.1\nisi_duration_s = 0.03\nfeedback = \"text\"\nfeedback_duration_s = 0.04";
  const std::string db = scratch.file("r.db");
  const auto result = run_glarelab({"run", write_experiment(scratch, setup), "--display", "offscreen", "--observer",
                                    "simulated", "--db", db},
                                   scratch.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const ResultStore store(db);
  const auto roundings = events(store, "duration_rounding");
  ASSERT_EQ(roundings.size(), 4u);
  EXPECT_EQ(roundings[0], "stimulus_duration_s 0.05 s -> 3 frames = 0.05 s at 60 Hz (rounding 0 ms)");
  EXPECT_EQ(roundings[1], "presentation.fixation_duration_s 0.1 s -> 6 frames = 0.1 s at 60 Hz (rounding 0 ms)");
  EXPECT_EQ(roundings[2].rfind("presentation.isi_duration_s 0.03 s -> 2 frames = 0.0333333 s at 60 Hz (rounding 3.33", 0), 0u)
      << roundings[2];
  EXPECT_EQ(roundings[3].rfind("presentation.feedback_duration_s 0.04 s -> 2 frames = 0.0333333 s at 60 Hz (rounding -6.66", 0),
            0u)
      << roundings[3];
  // One trial (side by side): fixation 6, stimulus 3, feedback 2; the inter-stimulus interval only
  // comes between trials.
  EXPECT_EQ(events(store, "trial_phases"),
            (std::vector<std::string>{"trial 0: fixation 6, interval 1 3 (frames 0-2), feedback 2 flips"}));
}

TEST(PresentationSession, BadPresentationValueStopsTheRunAtItsLine) {
  const ScratchDir scratch;
  StudySetup setup;
  setup.presentation = "fixation_frames = -1";
  const std::string experiment = write_experiment(scratch, setup);
  const auto result = run_glarelab({"run", experiment, "--display", "offscreen", "--observer", "simulated", "--db",
                                    scratch.file("bad.db")},
                                   scratch.path());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find(experiment + ":28:19: key 'presentation.fixation_frames': must be >= 0, found -1"),
            std::string::npos)
      << result.output;
  EXPECT_FALSE(std::filesystem::exists(scratch.file("bad.db")));
}

}  // namespace
}  // namespace glarelab

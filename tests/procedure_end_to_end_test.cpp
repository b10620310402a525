// Every procedure (forced choice with 2 and 3 alternatives, staircase, QUEST, adjustment, rating)
// runs end to end offscreen, as a user runs it, with a script observer -- every column of every
// trial row checked against values worked out by hand from the script -- and with the simulated
// observer, each row checked against the procedure's own definition of its columns.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "protocols/staircase.h"
#include "runner/store/result_store.h"
#include "cli_process.h"

namespace glarelab {
namespace {

using test::run_glarelab;
using test::ScratchDir;

const std::string kScenes = std::string(GLARELAB_SOURCE_DIR) + "/examples/scenes/";

// A small display and one frame per trial keep each run short.
std::string experiment(const std::string& procedure, const std::string& rows) {
  return "[experiment]\nname = \"end-to-end\"\nseed = 5\n"
         "[display]\nwidth_px = 128\nheight_px = 64\n"
         "[scenes]\n"
         "lamp_100 = { file = \"" + kScenes + "lamp_100.exr\" }\n"
         "lamp_130 = { file = \"" + kScenes + "lamp_130.exr\" }\n"
         "lamp_160 = { file = \"" + kScenes + "lamp_160.exr\" }\n"
         "[procedure]\nstimulus_frames = 1\n" + procedure + "\n" + rows;
}

const std::string kForcedChoice2 = experiment(
    "type = \"forced_choice\"",
    "[[conditions.rows]]\nname = \"right brighter\"\nscene_a = \"lamp_100\"\nscene_b = \"lamp_130\"\n"
    "[[conditions.rows]]\nname = \"left brighter\"\nscene_a = \"lamp_160\"\nscene_b = \"lamp_100\"\n");
const std::string kForcedChoice3 = experiment(
    "type = \"forced_choice\"\nalternatives = 3",
    "[[conditions.rows]]\nname = \"equal\"\nscene_a = \"lamp_100\"\nscene_b = \"lamp_100\"\n"
    "[[conditions.rows]]\nname = \"unequal\"\nscene_a = \"lamp_100\"\nscene_b = \"lamp_130\"\n");
// Linear 10 cd/m2 steps, 1-up/1-down: the intensities of a script are easy to follow by hand.
const std::string kStaircase = experiment(
    "type = \"staircase\"\nstart_intensity = 150.0\nstep_type = \"lin\"\nstep_sizes = [10.0]\n"
    "n_up = 1\nn_down = 1\nn_reversals = 2\nn_trials = 4",
    "[[conditions.rows]]\nname = \"lamp\"\nreference = \"lamp_100\"\ncomparison = \"lamp_130\"\n");
const std::string kQuest = experiment("type = \"quest\"\nt_guess = 2.1\nn_trials = 3",
                                      "[[conditions.rows]]\nname = \"lamp\"\nreference = \"lamp_100\"\n"
                                      "comparison = \"lamp_130\"\n");
const std::string kAdjustment = experiment(
    "type = \"adjustment\"\nrepetitions = 2",
    "[[conditions.rows]]\nname = \"low\"\ntarget = \"lamp_100\"\ncomparison = \"lamp_100\"\n");
const std::string kRating = experiment("type = \"rating\"\ncategories = [\"glare\", \"overall\"]",
                                       "[[conditions.rows]]\nname = \"one\"\nscene = \"lamp_130\"\n");

const std::map<std::string, double> kPeakCdM2 = {{"lamp_100", 100.0}, {"lamp_130", 130.0}, {"lamp_160", 160.0}};

struct SessionRows {
  std::vector<TrialRecord> trials;
  std::vector<std::vector<AdjustmentSetting>> settings;  // per trial
};

SessionRows run_offscreen(const ScratchDir& scratch, const std::string& text, const std::string& observer) {
  const std::string name = std::to_string(std::hash<std::string>{}(text + observer));
  const std::string file = scratch.write(name + ".toml", text);
  const auto db = scratch.path() / (name + ".db");
  const auto result = run_glarelab({"run", file, "--display", "offscreen", "--observer", observer, "--db", db.string()},
                                   scratch.path());
  SessionRows run;
  EXPECT_EQ(result.exit_code, 0) << result.output;
  if (result.exit_code != 0) return run;
  const ResultStore store(db.string());
  const auto sessions = store.load_sessions();
  EXPECT_EQ(sessions.size(), 1u);
  EXPECT_EQ(sessions.at(0).status, "completed");
  run.trials = store.load_trials(sessions.at(0).id);
  for (const TrialRecord& trial : run.trials) run.settings.push_back(store.load_adjustments(trial.id));
  return run;
}

std::string script(const ScratchDir& scratch, const std::string& name, const std::string& lines) {
  return "script:" + scratch.write(name, lines);
}

// The scene named by a "key":"value" member of the trial's condition JSON.
std::string member(const TrialRecord& trial, const std::string& key) {
  const std::string needle = "\"" + key + "\":\"";
  const auto start = trial.condition.find(needle);
  if (start == std::string::npos) return "";
  const auto end = trial.condition.find('"', start + needle.size());
  return trial.condition.substr(start + needle.size(), end - start - needle.size());
}

TEST(ProcedureEndToEnd, ForcedChoiceTwoAndThreeWayWithAScript) {
  const ScratchDir scratch;
  // Two rows both ways round: 4 trials, each answered "left". Left is right exactly when the
  // brighter lamp (130 or 160 against 100) is on the left: once per row.
  const SessionRows two = run_offscreen(scratch, kForcedChoice2, script(scratch, "left.txt", "left\nleft\nleft\nleft\n"));
  ASSERT_EQ(two.trials.size(), 4u);
  int correct = 0;
  for (const TrialRecord& t : two.trials) {
    EXPECT_EQ(t.procedure, "forced_choice");
    EXPECT_EQ(t.response, "left");
    EXPECT_FALSE(t.intensity.has_value());
    EXPECT_FALSE(t.reversal.has_value());
    ASSERT_TRUE(t.correct.has_value());
    EXPECT_EQ(*t.correct, member(t, "left") != "lamp_100" ? 1 : 0) << t.condition;
    correct += *t.correct;
  }
  EXPECT_EQ(correct, 2);
  // 3-way, every answer "neither": right for the two trials of equal lamps, wrong for the others.
  const SessionRows three =
      run_offscreen(scratch, kForcedChoice3, script(scratch, "neither.txt", "neither\nneither\nneither\nneither\n"));
  ASSERT_EQ(three.trials.size(), 4u);
  std::map<std::string, int> correct_by_row;
  for (const TrialRecord& t : three.trials) {
    EXPECT_EQ(t.procedure, "forced_choice");
    EXPECT_EQ(t.response, "neither");
    EXPECT_FALSE(t.intensity.has_value());
    EXPECT_FALSE(t.reversal.has_value());
    ASSERT_TRUE(t.correct.has_value());
    correct_by_row[member(t, "name")] += *t.correct;
  }
  EXPECT_EQ(correct_by_row, (std::map<std::string, int>{{"equal", 2}, {"unequal", 0}}));
}

TEST(ProcedureEndToEnd, StaircaseAndQuestWithAScript) {
  const ScratchDir scratch;
  // Correct, correct, wrong, correct from 150 cd/m2 in 10 cd/m2 steps: down to 140 and 130, up to
  // 140 (first reversal), down again (second reversal); two reversals and four trials end it.
  const SessionRows staircase = run_offscreen(scratch, kStaircase, script(scratch, "s.txt", "1\n1\n0\n1\n"));
  ASSERT_EQ(staircase.trials.size(), 4u);
  const std::vector<double> intensity = {150.0, 140.0, 130.0, 140.0};
  const std::vector<int> correct = {1, 1, 0, 1}, reversal = {0, 0, 1, 1};
  for (std::size_t i = 0; i < 4; ++i) {
    const TrialRecord& t = staircase.trials[i];
    EXPECT_EQ(t.procedure, "staircase");
    EXPECT_EQ(t.staircase, "staircase");
    ASSERT_TRUE(t.intensity && t.correct && t.reversal) << i;
    EXPECT_NEAR(*t.intensity, intensity[i], 1e-9) << i;
    EXPECT_EQ(*t.correct, correct[i]) << i;
    EXPECT_EQ(*t.reversal, reversal[i]) << i;
    // The comparison (lamp_130 scaled to at least 130 cd/m2) is the brighter source: "1" names
    // its side, "0" the reference's.
    const std::string comparison_side = member(t, "left") == "lamp_130" ? "left" : "right";
    const std::string reference_side = comparison_side == "left" ? "right" : "left";
    EXPECT_EQ(t.response, correct[i] == 1 ? comparison_side : reference_side) << t.condition;
  }
  // QUEST starts at t_guess (10^2.1 cd/m2); reversal is 0 for QUEST.
  const SessionRows quest = run_offscreen(scratch, kQuest, script(scratch, "q.txt", "1\n0\n1\n"));
  ASSERT_EQ(quest.trials.size(), 3u);
  ASSERT_TRUE(quest.trials[0].intensity.has_value());
  EXPECT_NEAR(*quest.trials[0].intensity, std::pow(10.0, 2.1), 1e-9 * std::pow(10.0, 2.1));
  for (std::size_t i = 0; i < 3; ++i) {
    const TrialRecord& t = quest.trials[i];
    EXPECT_EQ(t.procedure, "quest");
    ASSERT_TRUE(t.intensity && t.correct && t.reversal);
    EXPECT_EQ(*t.correct, i == 1 ? 0 : 1);
    EXPECT_EQ(*t.reversal, 0);
  }
  EXPECT_NE(*quest.trials[1].intensity, *quest.trials[0].intensity) << "QUEST moved after the first answer";
}

TEST(ProcedureEndToEnd, AdjustmentAndRatingWithAScript) {
  const ScratchDir scratch;
  const SessionRows adjustment = run_offscreen(scratch, kAdjustment, script(scratch, "a.txt", "120 130\n90\n"));
  ASSERT_EQ(adjustment.trials.size(), 2u);
  const std::vector<std::string> response = {"120 130", "90"};
  const std::vector<double> mean = {125.0, 90.0};
  const std::vector<std::vector<double>> settings = {{120.0, 130.0}, {90.0, 90.0}};
  for (std::size_t i = 0; i < 2; ++i) {
    const TrialRecord& t = adjustment.trials[i];
    EXPECT_EQ(t.procedure, "adjustment");
    EXPECT_EQ(t.response, response[i]);
    ASSERT_TRUE(t.intensity.has_value());
    EXPECT_DOUBLE_EQ(*t.intensity, mean[i]);
    EXPECT_FALSE(t.correct.has_value());
    EXPECT_FALSE(t.reversal.has_value());
    ASSERT_EQ(adjustment.settings[i].size(), 2u);
    EXPECT_DOUBLE_EQ(adjustment.settings[i][0].value_cd_m2, settings[i][0]);
    EXPECT_DOUBLE_EQ(adjustment.settings[i][1].value_cd_m2, settings[i][1]);
  }
  const SessionRows rating = run_offscreen(scratch, kRating, script(scratch, "r.txt", "4\n2\n"));
  ASSERT_EQ(rating.trials.size(), 2u);
  std::map<std::string, std::string> by_category;
  for (std::size_t i = 0; i < 2; ++i) {
    const TrialRecord& t = rating.trials[i];
    EXPECT_EQ(t.procedure, "rating");
    EXPECT_EQ(t.response, i == 0 ? "4" : "2");
    EXPECT_FALSE(t.intensity.has_value());
    EXPECT_FALSE(t.correct.has_value());
    EXPECT_FALSE(t.reversal.has_value());
    by_category[member(t, "category")] = t.response;
  }
  EXPECT_EQ(by_category.size(), 2u) << "each category once";
}

// With the simulated observer each row must satisfy the procedure's definitions: correct names
// the brighter source, the staircase's intensities and reversals replay through StairHandler
// semantics, the adjustment's intensity is the mean of its settings, ratings are on the scale.
TEST(ProcedureEndToEnd, EveryProcedureWithTheSimulatedObserver) {
  const ScratchDir scratch;
  for (const std::string* text : {&kForcedChoice2, &kForcedChoice3}) {
    const SessionRows run = run_offscreen(scratch, *text, "simulated");
    ASSERT_EQ(run.trials.size(), 4u);
    for (const TrialRecord& t : run.trials) {
      EXPECT_EQ(t.procedure, "forced_choice");
      EXPECT_FALSE(t.intensity.has_value());
      EXPECT_FALSE(t.reversal.has_value());
      const double left = kPeakCdM2.at(member(t, "left")), right = kPeakCdM2.at(member(t, "right"));
      const std::string right_answer = left == right ? "neither" : left > right ? "left" : "right";
      ASSERT_TRUE(t.correct.has_value()) << t.condition;
      EXPECT_EQ(*t.correct, t.response == right_answer ? 1 : 0) << t.condition << " " << t.response;
    }
  }

  const SessionRows staircase = run_offscreen(scratch, kStaircase, "simulated");
  StaircaseSpec spec;
  spec.start_value = 150.0;
  spec.step_type = StepType::lin;
  spec.step_sizes = {10.0};
  spec.n_up = 1;
  spec.n_down = 1;
  spec.n_reversals = 2;
  spec.n_trials = 4;
  Staircase reference(spec);
  ASSERT_GE(staircase.trials.size(), 4u);
  for (const TrialRecord& t : staircase.trials) {
    EXPECT_EQ(t.procedure, "staircase");
    ASSERT_TRUE(t.intensity && t.correct && t.reversal);
    EXPECT_NEAR(*t.intensity, reference.next_intensity(), 1e-9);
    const std::string comparison_side = member(t, "left") == "lamp_130" ? "left" : "right";
    const bool brighter = *t.intensity >= 100.0;  // equal sources: the comparison's side counts as correct
    EXPECT_EQ(*t.correct, (t.response == comparison_side) == brighter ? 1 : 0) << t.condition;
    EXPECT_EQ(*t.reversal, reference.add_response(*t.correct == 1) ? 1 : 0);
  }
  EXPECT_TRUE(reference.finished());

  const SessionRows quest = run_offscreen(scratch, kQuest, "simulated");
  ASSERT_EQ(quest.trials.size(), 3u);
  for (const TrialRecord& t : quest.trials) {
    EXPECT_EQ(t.procedure, "quest");
    ASSERT_TRUE(t.intensity && t.correct && t.reversal);
    EXPECT_EQ(*t.reversal, 0);
    const std::string comparison_side = member(t, "left") == "lamp_130" ? "left" : "right";
    EXPECT_EQ(*t.correct, (t.response == comparison_side) == (*t.intensity >= 100.0) ? 1 : 0);
  }

  const SessionRows adjustment = run_offscreen(scratch, kAdjustment, "simulated");
  ASSERT_EQ(adjustment.trials.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const TrialRecord& t = adjustment.trials[i];
    EXPECT_EQ(t.procedure, "adjustment");
    ASSERT_EQ(adjustment.settings[i].size(), 2u);
    ASSERT_TRUE(t.intensity.has_value());
    EXPECT_DOUBLE_EQ(*t.intensity, 0.5 * (adjustment.settings[i][0].value_cd_m2 + adjustment.settings[i][1].value_cd_m2));
    EXPECT_FALSE(t.correct.has_value());
    EXPECT_FALSE(t.reversal.has_value());
  }

  const SessionRows rating = run_offscreen(scratch, kRating, "simulated");
  ASSERT_EQ(rating.trials.size(), 2u);
  for (const TrialRecord& t : rating.trials) {
    EXPECT_EQ(t.procedure, "rating");
    const int value = std::stoi(t.response);
    EXPECT_GE(value, 1);
    EXPECT_LE(value, 5);
    EXPECT_FALSE(t.intensity.has_value());
    EXPECT_FALSE(t.correct.has_value());
    EXPECT_FALSE(t.reversal.has_value());
  }
}

}  // namespace
}  // namespace glarelab

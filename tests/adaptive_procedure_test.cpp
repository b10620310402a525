// Staircases and QUEST through the Procedure interface: every trial shows what the Staircase and
// Quest classes (tested against PsychoPy and Psychtoolbox in staircase_test and quest_test) ask
// for, interleaving follows InterleavedStaircases, and replaying responses restores the state.
#include <gtest/gtest.h>

#include <cmath>

#include "protocols/adaptive_procedure.h"

namespace glarelab {
namespace {

const std::map<std::string, double> kPeaks = {{"ref", 100.0}, {"cmp", 80.0}};

Experiment adaptive_experiment(const std::string& procedure, std::vector<AdaptiveTrackSpec> tracks, int alternatives) {
  Experiment e;
  e.name = "adaptive";
  e.seed = 99;
  e.procedure = procedure;
  e.forced_choice.alternatives = alternatives;
  if (alternatives == 3) e.forced_choice.responses = {"left", "right", "neither"};
  ConditionRow row;
  row.fields = {{"name", "lamp"}, {"reference", "ref"}, {"comparison", "cmp"}};
  row.number = 1;
  e.conditions.push_back(row);
  e.adaptive.tracks = std::move(tracks);
  return e;
}

AdaptiveTrackSpec staircase_track(const std::string& name, double start) {
  AdaptiveTrackSpec track;
  track.staircase.name = name;
  track.staircase.start_value = start;
  track.staircase.step_sizes = {4.0, 2.0};
  track.staircase.n_reversals = 4;
  track.staircase.n_trials = 12;
  track.staircase.n_up = 1;
  track.staircase.n_down = 2;
  return track;
}

// A fixed, irregular pattern of correct (1) and incorrect (0) answers.
bool answer_correct(int trial) { return ((trial * 7 + 3) % 5) < 3; }

std::string answer(const TrialPlan& plan, bool correct) {
  if (correct) return plan.correct_response;
  for (const std::string& r : plan.allowed_responses)
    if (r != plan.correct_response) return r;
  return "";
}

TEST(AdaptiveProcedure, StaircaseTrialsFollowTheStaircaseClass) {
  const Experiment e = adaptive_experiment("staircase", {staircase_track("s", 150.0)}, 2);
  AdaptiveProcedure procedure(e, kPeaks);
  Staircase reference(e.adaptive.tracks[0].staircase);
  int trial = 0;
  while (!procedure.finished()) {
    ASSERT_FALSE(reference.finished());
    const TrialPlan plan = procedure.next_trial();
    ASSERT_TRUE(plan.intensity.has_value());
    EXPECT_NEAR(*plan.intensity, reference.next_intensity(), 1e-12);
    // The comparison (peak 80 cd/m2) is scaled to show the intensity; the reference is unscaled.
    const std::size_t cmp = plan.scenes[0] == "cmp" ? 0 : 1;
    EXPECT_NEAR(plan.scene_scale[cmp] * 80.0, *plan.intensity, 1e-9);
    EXPECT_EQ(plan.scene_scale[1 - cmp], 1.0);
    EXPECT_EQ(plan.correct_response, plan.positions[*plan.intensity > 100.0 ? cmp : 1 - cmp]);
    const bool correct = answer_correct(trial);
    const TrialOutcome outcome = procedure.record_response(plan, {answer(plan, correct), 0.5});
    const bool reversal = reference.add_response(correct);
    EXPECT_EQ(outcome.correct, correct ? 1 : 0);
    EXPECT_EQ(outcome.reversal, reversal ? 1 : 0);
    EXPECT_EQ(outcome.staircase, "s");
    ++trial;
  }
  EXPECT_TRUE(reference.finished());
  EXPECT_EQ(trial, reference.trial_count());
  EXPECT_GE(trial, 12);
}

TEST(AdaptiveProcedure, InterleavingFollowsInterleavedStaircases) {
  const Experiment e =
      adaptive_experiment("staircase", {staircase_track("up", 60.0), staircase_track("down", 200.0)}, 2);
  AdaptiveProcedure procedure(e, kPeaks);
  InterleavedStaircases reference({e.adaptive.tracks[0].staircase, e.adaptive.tracks[1].staircase}, e.seed);
  int trial = 0;
  while (!procedure.finished()) {
    const std::optional<std::size_t> index = reference.next();
    ASSERT_TRUE(index.has_value());
    const TrialPlan plan = procedure.next_trial();
    EXPECT_EQ(plan.staircase, reference.at(*index).spec().name) << "trial " << trial;
    EXPECT_NEAR(*plan.intensity, reference.at(*index).next_intensity(), 1e-12);
    const bool correct = answer_correct(trial);
    procedure.record_response(plan, {answer(plan, correct), 0.5});
    reference.at(*index).add_response(correct);
    ++trial;
  }
  EXPECT_TRUE(reference.finished());
}

TEST(AdaptiveProcedure, ReplayingResponsesRestoresTheState) {
  const Experiment e =
      adaptive_experiment("staircase", {staircase_track("up", 60.0), staircase_track("down", 200.0)}, 3);
  AdaptiveProcedure original(e, kPeaks);
  std::vector<std::string> responses;
  for (int trial = 0; trial < 9; ++trial) {
    const TrialPlan plan = original.next_trial();
    responses.push_back(answer_correct(trial) ? plan.correct_response : "neither");
    original.record_response(plan, {responses.back(), 0.5});
  }
  AdaptiveProcedure replayed(e, kPeaks);
  for (const std::string& response : responses) replayed.record_response(replayed.next_trial(), {response, 0.5});
  const TrialPlan a = original.next_trial();
  const TrialPlan b = replayed.next_trial();
  EXPECT_EQ(a.trial_index, 9);
  EXPECT_EQ(a.trial_index, b.trial_index);
  EXPECT_EQ(a.condition_json, b.condition_json);
  EXPECT_EQ(*a.intensity, *b.intensity);
}

TEST(AdaptiveProcedure, QuestShowsTenToItsLogIntensity) {
  AdaptiveTrackSpec track;
  track.quest.name = "q";
  track.quest.t_guess = 2.0;  // 100 cd/m2
  track.quest.t_guess_sd = 0.5;
  track.quest.n_trials = 15;
  const Experiment e = adaptive_experiment("quest", {track}, 2);
  AdaptiveProcedure procedure(e, kPeaks);
  Quest reference(track.quest);
  int trial = 0;
  while (!procedure.finished()) {
    const TrialPlan plan = procedure.next_trial();
    EXPECT_NEAR(*plan.intensity, std::pow(10.0, reference.next_intensity()), 1e-9);
    const bool correct = answer_correct(trial);
    const TrialOutcome outcome = procedure.record_response(plan, {answer(plan, correct), 0.5});
    EXPECT_EQ(outcome.reversal, 0);
    reference.add_response(correct);
    ++trial;
  }
  EXPECT_EQ(trial, 15);
  EXPECT_NEAR(procedure.quest(0)->mean(), reference.mean(), 1e-12);
}

TEST(AdaptiveProcedure, EqualSourcesMakeNeitherCorrectInTheThreeWayTask) {
  AdaptiveTrackSpec track = staircase_track("s", 100.0);  // the reference's own luminance
  const Experiment e = adaptive_experiment("staircase", {track}, 3);
  AdaptiveProcedure procedure(e, kPeaks);
  EXPECT_EQ(procedure.next_trial().correct_response, "neither");
}

}  // namespace
}  // namespace glarelab

// The Procedure interface: forced choice through it hands out exactly the design that
// build_forced_choice_trials builds, and only answers move it on.
#include <gtest/gtest.h>

#include "protocols/forced_choice.h"
#include "protocols/procedure.h"

namespace glarelab {
namespace {

Experiment two_pairs(std::uint64_t seed) {
  Experiment e;
  e.name = "procedure";
  e.seed = seed;
  e.forced_choice.repetitions = 2;
  const char* pairs[][3] = {{"p1", "a", "b"}, {"p2", "b", "c"}};
  int number = 1;
  for (const auto& pair : pairs) {
    ConditionRow row;
    row.fields = {{"name", pair[0]}, {"scene_a", pair[1]}, {"scene_b", pair[2]}};
    row.number = number++;
    e.conditions.push_back(row);
  }
  return e;
}

const std::map<std::string, double> kPeaks = {{"a", 100.0}, {"b", 200.0}, {"c", 50.0}};

TEST(Procedure, ForcedChoiceHandsOutTheBuiltDesignInOrder) {
  const Experiment e = two_pairs(7);
  const std::vector<TrialPlan> reference = build_forced_choice_trials(e, kPeaks);
  auto procedure = make_procedure(e, kPeaks);
  ASSERT_EQ(procedure->planned_trials(), static_cast<int>(reference.size()));
  for (const TrialPlan& expected : reference) {
    ASSERT_FALSE(procedure->finished());
    const TrialPlan plan = procedure->next_trial();
    EXPECT_EQ(plan.trial_index, expected.trial_index);
    EXPECT_EQ(plan.condition_json, expected.condition_json);
    EXPECT_EQ(plan.scenes, expected.scenes);
    EXPECT_EQ(procedure->next_trial().condition_json, plan.condition_json) << "next_trial must not advance";
    const TrialOutcome outcome = procedure->record_response(plan, {"left", 0.4});
    // Scored as score_forced_choice does: correct when the left source is the brighter one.
    EXPECT_EQ(outcome.correct, plan.source_luminance_cd_m2[0] > plan.source_luminance_cd_m2[1] ? 1 : 0);
  }
  EXPECT_TRUE(procedure->finished());
}

TEST(Procedure, AbortDoesNotAdvanceAndAStaleResponseIsRefused) {
  const Experiment e = two_pairs(3);
  auto procedure = make_procedure(e, kPeaks);
  const TrialPlan first = procedure->next_trial();
  const TrialOutcome aborted = procedure->record_response(first, {"abort", std::nullopt});
  EXPECT_FALSE(aborted.correct.has_value());
  EXPECT_EQ(procedure->next_trial().trial_index, 0);
  procedure->record_response(first, {"right", 0.5});
  EXPECT_EQ(procedure->next_trial().trial_index, 1);
  EXPECT_THROW(procedure->record_response(first, {"right", 0.5}), std::logic_error);
}

TEST(Procedure, UnknownProcedureIsRefused) {
  Experiment e = two_pairs(1);
  e.procedure = "method_of_limits";
  EXPECT_THROW(make_procedure(e, kPeaks), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab

// The staircase analysis takes a fit's guess rate from the task: the condition's guess_rate or
// alternatives, else the procedure's `alternatives` stored with the session (a 3-way task with
// "neither" guesses 1/3), and only without either assumes two alternatives, saying so.
#include <gtest/gtest.h>

#include "analysis/loaded_database.h"
#include "analysis/staircase_analysis.h"
#include "analysis/stored_procedure.h"

namespace glarelab::analysis {
namespace {

LoadedData staircase_session(const std::string& config, const ConditionFields& condition = {}) {
  LoadedSession session;
  session.label = "p1 (db#1)";
  session.record.config = config;
  for (int k = 0; k < 12; ++k) {
    LoadedTrial trial;
    trial.record.trial_index = k;
    trial.record.procedure = "staircase";
    trial.record.staircase = "track";
    trial.record.intensity = 100.0 + 10.0 * (k % 4);
    trial.record.correct = k % 3 == 0 ? 0 : 1;
    trial.record.reversal = k % 3 == 0 ? 1 : 0;
    trial.condition = condition;
    session.trials.push_back(trial);
  }
  LoadedData data;
  data.sessions.push_back(session);
  return data;
}

StaircaseResult analyse(const LoadedData& data) {
  StaircaseOptions options;
  options.bootstrap_samples = 0;
  options.threads = 1;
  const std::vector<StaircaseResult> results = analyse_staircases(data, options);
  EXPECT_EQ(results.size(), 1u);
  return results.empty() ? StaircaseResult{} : results.front();
}

TEST(AnalysisGuessRate, ThreeWayProcedureStoredWithTheSessionGuessesAThird) {
  const StaircaseResult result = analyse(staircase_session("[procedure]\ntype = \"staircase\"\nalternatives = 3\n"));
  EXPECT_DOUBLE_EQ(result.guess_rate, 1.0 / 3.0);
  EXPECT_NE(result.guess_note.find("alternatives = 3"), std::string::npos) << result.guess_note;
  EXPECT_EQ(result.guess_note.find("assumed"), std::string::npos) << result.guess_note;
}

TEST(AnalysisGuessRate, ConditionValuesComeFirstAndTwoAlternativesAreOnlyAssumedWithoutAnyStatement) {
  EXPECT_DOUBLE_EQ(analyse(staircase_session("[procedure]\nalternatives = 3\n", {{"guess_rate", "0.25"}})).guess_rate, 0.25);
  EXPECT_DOUBLE_EQ(analyse(staircase_session("[procedure]\nalternatives = 3\n", {{"alternatives", "4"}})).guess_rate, 0.25);
  const StaircaseResult unknown = analyse(staircase_session("[experiment]\nname = \"old\"\n"));
  EXPECT_DOUBLE_EQ(unknown.guess_rate, 0.5);
  EXPECT_NE(unknown.guess_note.find("assumed"), std::string::npos) << unknown.guess_note;
  EXPECT_EQ(stored_alternatives("not toml ["), std::nullopt);
  EXPECT_EQ(stored_alternatives("[procedure]\nalternatives = 2\n"), 2);
}

}  // namespace
}  // namespace glarelab::analysis

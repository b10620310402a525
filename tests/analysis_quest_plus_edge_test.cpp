// QUEST+ marginals in the report (analysis/quest_plus_posterior.h): the central 95 % interval read
// off a marginal worked by hand, and the warning when an estimate sits at a grid edge.
#include <gtest/gtest.h>

#include "analysis/quest_plus_posterior.h"

namespace glarelab::analysis {
namespace {

MarginalPosterior marginal(std::vector<double> probabilities, double mode, double mean) {
  MarginalPosterior m;
  m.parameter = "threshold";
  m.unit = "dB cd/m2";
  for (std::size_t i = 0; i < probabilities.size(); ++i) m.values.push_back(40.2 + 2.0 * static_cast<double>(i));
  m.probabilities = std::move(probabilities);
  m.mode = mode;
  m.mean = mean;
  return m;
}

// Cumulative 0.01, 0.04, 0.34, 0.84, 0.98, 1.0: 0.025 is first reached at the 2nd value (42.2),
// 0.975 at the 5th (48.2).
TEST(AnalysisQuestPlusEdge, CredibleIntervalFromTheCumulative) {
  const MarginalPosterior m = marginal({0.01, 0.03, 0.30, 0.50, 0.14, 0.02}, 46.2, 45.9);
  const auto [low, high] = marginal_credible_interval(m);
  EXPECT_DOUBLE_EQ(low, 42.2);
  EXPECT_DOUBLE_EQ(high, 48.2);
  EXPECT_TRUE(grid_edge_warning(m).empty());
}

// The case: the mode at the grid's lowest value (40.2 dB) must not pass without a word.
TEST(AnalysisQuestPlusEdge, ModeAtTheLowestValueIsFlagged) {
  const MarginalPosterior low = marginal({0.6, 0.3, 0.1, 0.0, 0.0, 0.0}, 40.2, 41.2);
  const std::string warning = grid_edge_warning(low);
  EXPECT_NE(warning.find("lowest value (40.2 dB cd/m2)"), std::string::npos) << warning;
  const MarginalPosterior high = marginal({0.0, 0.0, 0.0, 0.1, 0.2, 0.7}, 50.2, 49.4);
  EXPECT_NE(grid_edge_warning(high).find("highest value (50.2"), std::string::npos) << grid_edge_warning(high);
  // The report's table, terminal line and figure carry it.
  QuestPlusPosterior track;
  track.participant_label = "P1";
  track.track = "t";
  track.method = "quest_plus";
  track.trials = 20;
  track.marginals = {low};
  EXPECT_NE(quest_plus_posteriors_html({track}).find("warning: the threshold mode"), std::string::npos);
  EXPECT_NE(quest_plus_posteriors_terminal({track}).find("warning: the threshold mode"), std::string::npos);
  EXPECT_NE(marginal_posterior_svg(track, 0).find("warning:"), std::string::npos);  // the note may wrap after it
}

}  // namespace
}  // namespace glarelab::analysis

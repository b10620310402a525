// The rating analysis on awkward data: answers that are not numbers, trials that name no
// category, repeated ratings of a cell, unanswered trials and a condition rated by one
// participant only. Each gives numbers worked out here or a statement, never NaN.
#include <gtest/gtest.h>

#include "analysis/analysis_report.h"
#include "analysis/report_output.h"
#include "tests/analysis_synthetic.h"
#include "tests/scratch_dir.h"

namespace glarelab::analysis {
namespace {

test::TrialSpec rating(const std::string& condition_json, const std::string& response) {
  return {"rating", condition_json, response, {}, {}, "", {}};
}

RatingAnalysis analyse_sessions(const test::ScratchDir& dir, const std::vector<std::vector<test::TrialSpec>>& sessions) {
  const std::string path = dir.file("cases.db");
  {
    ResultStore store(path);
    for (std::size_t p = 0; p < sessions.size(); ++p) {
      const auto id = store.begin_session(test::synthetic_session("P" + std::to_string(p + 1)));
      test::commit_trials(store, id, sessions[p]);
      store.finish_session(id, "completed");
    }
  }
  return analyse_ratings(load_databases({path}));
}

TEST(AnalysisRatingCases, WordsAndNonFiniteTextAreNotRatings) {
  for (const std::string odd : {"good", "nan", "inf"}) {
    const test::ScratchDir dir;
    const RatingAnalysis r =
        analyse_sessions(dir, {{rating("{\"name\":\"A\",\"category\":\"look\"}", "3"),
                                rating("{\"name\":\"A\",\"category\":\"look\"}", odd)}});
    ASSERT_EQ(r.cells.size(), 1u) << odd;
    EXPECT_FALSE(r.cells[0].mean.has_value()) << odd;
    EXPECT_TRUE(r.comparisons.empty()) << odd;
    ASSERT_EQ(r.notes.size(), 1u);
    EXPECT_EQ(r.notes[0], "not every rating is a number: no means, medians or rank tests");
    // Distribution in text order: "3" before the word.
    EXPECT_EQ(r.cells[0].categories, (std::vector<std::pair<std::string, long>>{{"3", 1}, {odd, 1}}));
  }
}

// Two participants rate A and B with no category; P1 rates each twice. Scores: P1 A (2 + 5)/2 =
// 3.5, B (1 + 2)/2 = 1.5; P2 A 4, B 4 (a zero difference). One difference is left, +2: exact, p
// = 2 * P(R+ >= 1 | n = 1) = 1. Unanswered and aborted trials are counted as trials only.
TEST(AnalysisRatingCases, RepeatedRatingsAreAveragedAndZerosDropped) {
  const test::ScratchDir dir;
  const std::string a = "{\"name\":\"A\"}";
  const std::string b = "{\"name\":\"B\"}";
  const RatingAnalysis r = analyse_sessions(
      dir, {{rating(a, "2"), rating(b, "1"), rating(a, "5"), rating(b, "2"), rating(a, ""), rating(b, "abort")},
            {rating(a, "4"), rating(b, "4")}});
  EXPECT_EQ(r.trials, 8);
  ASSERT_EQ(r.category_order, (std::vector<std::string>{""}));
  ASSERT_EQ(r.comparisons.size(), 1u);
  const RatingComparison& c = r.comparisons[0];
  EXPECT_EQ(c.conditions, (std::vector<std::string>{"A", "B"}));
  EXPECT_EQ(c.scores, (std::vector<std::vector<double>>{{3.5, 1.5}, {4.0, 4.0}}));
  ASSERT_TRUE(c.wilcoxon.has_value());
  ASSERT_TRUE(c.wilcoxon->ok()) << c.wilcoxon->unavailable;
  EXPECT_EQ(c.wilcoxon->zero_differences, 1u);
  EXPECT_EQ(c.wilcoxon->ranked, 1u);
  EXPECT_FALSE(c.wilcoxon->exact) << "a zero difference rules out the exact distribution";
  // Normal approximation, n = 1: mean 0.5, variance 1*2*3/24 = 0.25; T = min(1, 0) = 0,
  // z = (0 - 0.5)/0.5 = -1.
  EXPECT_NEAR(c.wilcoxon->z, -1.0, 1e-15);
  // Medians and means of the cells: A over 2, 5, 4 and B over 1, 2, 4.
  ASSERT_EQ(r.cells.size(), 2u);
  EXPECT_NEAR(*r.cells[0].mean, 11.0 / 3.0, 1e-15);
  EXPECT_EQ(*r.cells[0].median, 4.0);
  EXPECT_EQ(*r.cells[1].median, 2.0);
}

TEST(AnalysisRatingCases, OneConditionOrAnIncompleteDesignIsAStatement) {
  const test::ScratchDir dir;
  const RatingAnalysis r = analyse_sessions(
      dir, {{rating("{\"name\":\"A\",\"category\":\"solo\"}", "3"), rating("{\"name\":\"A\",\"category\":\"pair\"}", "3")},
            {rating("{\"name\":\"B\",\"category\":\"pair\"}", "5")}});
  ASSERT_EQ(r.comparisons.size(), 2u);
  EXPECT_EQ(r.comparisons[0].unavailable, "only one condition was rated on this category: nothing to compare");
  EXPECT_EQ(r.comparisons[1].unavailable, "no participant rated every condition of this category");
  EXPECT_EQ(r.comparisons[1].left_out, (std::vector<std::string>{"P1", "P2"}));
}

}  // namespace
}  // namespace glarelab::analysis

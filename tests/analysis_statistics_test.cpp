// Statistics against published textbook values and exact hand-computed cases.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/statistics.h"

namespace glarelab::analysis {
namespace {

TEST(AnalysisStatistics, BinomialTwoSidedExactHandComputed) {
  // 9 of 10 at p = 1/2: P(X <= 1) + P(X >= 9) = 2 * (1 + 10) / 1024 = 22/1024.
  const TestResult nine = binomial_test_two_sided(9, 10);
  ASSERT_TRUE(nine.ok());
  EXPECT_NEAR(nine.p_value, 22.0 / 1024.0, 1e-15);
  // 5 of 10: every outcome is at most as likely as the mode -> p = 1.
  EXPECT_NEAR(binomial_test_two_sided(5, 10).p_value, 1.0, 1e-15);
  // 0 of 4: P(0) + P(4) = 2/16.
  EXPECT_NEAR(binomial_test_two_sided(0, 4).p_value, 2.0 / 16.0, 1e-15);
  // Asymmetric p: 3 of 15 at p = 0.1. P(3) = 0.12851; outcomes at most as likely: k = 3..15 and
  // none below (P(0) = 0.2059, P(1) = 0.3432, P(2) = 0.2669), so p = 1 - P(X <= 2) = 0.18406
  // (the value SciPy's documentation gives for the one-sided 'greater' test of the same data).
  EXPECT_NEAR(binomial_test_two_sided(3, 15, 0.1).p_value, 0.18406106910639114, 1e-12);
}

TEST(AnalysisStatistics, BinomialRefusesEmptyAndImpossibleInput) {
  EXPECT_FALSE(binomial_test_two_sided(0, 0).ok());
  EXPECT_FALSE(binomial_test_two_sided(5, 4).ok());
}

TEST(AnalysisStatistics, ChiSquareMendelPeas) {
  // Mendel's dihybrid cross (round-yellow 315, round-green 108, wrinkled-yellow 101,
  // wrinkled-green 32) against 9:3:3:1: chi2 = 0.470, df = 3, p = 0.925 (a standard textbook
  // example, e.g. Sokal & Rohlf, Biometry).
  const TestResult result = chi_square_goodness_of_fit({315, 108, 101, 32}, {9.0 / 16, 3.0 / 16, 3.0 / 16, 1.0 / 16});
  ASSERT_TRUE(result.ok());
  EXPECT_NEAR(result.statistic, 0.470, 0.0005);
  EXPECT_EQ(result.df1, 3.0);
  EXPECT_NEAR(result.p_value, 0.925, 0.0005);
}

TEST(AnalysisStatistics, ChiSquareNoPreferenceClosedForm) {
  // Two categories: chi2 = (a - b)^2 / (a + b); with df = 1 the p-value is erfc(sqrt(chi2 / 2)).
  const TestResult result = chi_square_goodness_of_fit({70, 30});
  ASSERT_TRUE(result.ok());
  EXPECT_NEAR(result.statistic, 16.0, 1e-12);
  EXPECT_NEAR(result.p_value, std::erfc(std::sqrt(8.0)), 1e-15);
}

TEST(AnalysisStatistics, ChiSquareZeroExpectedIsAStatement) {
  const TestResult result = chi_square_goodness_of_fit({0, 0});
  EXPECT_FALSE(result.ok());
  EXPECT_NE(result.unavailable.find("zero"), std::string::npos);
  EXPECT_FALSE(chi_square_goodness_of_fit({3, 4, 0}, {0.5, 0.5, 0.0}).ok());
}

TEST(AnalysisStatistics, PairedTStudentSleepData) {
  // Cushny & Peebles' hypnotics as used by Student (1908); R's
  // t.test(extra ~ group, data = sleep, paired = TRUE): t = -4.0621, df = 9, p-value = 0.002833.
  const std::vector<double> drug1 = {0.7, -1.6, -0.2, -1.2, -0.1, 3.4, 3.7, 0.8, 0.0, 2.0};
  const std::vector<double> drug2 = {1.9, 0.8, 1.1, 0.1, -0.1, 4.4, 5.5, 1.6, 4.6, 3.4};
  const TestResult result = paired_t_test(drug1, drug2);
  ASSERT_TRUE(result.ok());
  EXPECT_NEAR(result.statistic, -4.0621, 5e-5);
  EXPECT_EQ(result.df1, 9.0);
  EXPECT_NEAR(result.p_value, 0.002833, 5e-7);
}

TEST(AnalysisStatistics, PairedTNeedsTwoPairsAndVariance) {
  EXPECT_FALSE(paired_t_test({1.0}, {2.0}).ok());
  EXPECT_FALSE(paired_t_test({1.0, 2.0}, {2.0, 3.0}).ok());  // identical differences
}

TEST(AnalysisStatistics, RepeatedMeasuresAnovaFieldBushtucker) {
  // Field (2009), Discovering Statistics Using SPSS, 3rd ed., ch. 13: time to retch for 8
  // celebrities eating 4 animals. Published: F(3, 21) = 3.79, p = .026; Greenhouse-Geisser
  // epsilon = .533, corrected F(1.60, 11.19), p = .063.
  const std::vector<std::vector<double>> scores = {
      {8, 7, 1, 6}, {9, 5, 2, 5}, {6, 2, 3, 8}, {5, 3, 1, 9},
      {8, 4, 5, 8}, {7, 5, 6, 7}, {10, 2, 7, 2}, {12, 6, 8, 1}};
  const RepeatedMeasuresAnova result = repeated_measures_anova(scores);
  ASSERT_TRUE(result.ok()) << result.unavailable;
  EXPECT_NEAR(result.f, 3.79, 0.005);
  EXPECT_EQ(result.df_condition, 3.0);
  EXPECT_EQ(result.df_error, 21.0);
  EXPECT_NEAR(result.p_value, 0.026, 0.0005);
  EXPECT_NEAR(result.epsilon_gg, 0.533, 0.0005);
  EXPECT_NEAR(result.df_condition * result.epsilon_gg, 1.60, 0.005);
  EXPECT_NEAR(result.df_error * result.epsilon_gg, 11.19, 0.005);
  EXPECT_NEAR(result.p_value_gg, 0.063, 0.0005);
}

TEST(AnalysisStatistics, RepeatedMeasuresAnovaTwoLevelsIsPairedTSquared) {
  // With two levels F = t^2 of the paired test and epsilon = 1.
  const std::vector<double> a = {0.7, -1.6, -0.2, -1.2, -0.1, 3.4, 3.7, 0.8, 0.0, 2.0};
  const std::vector<double> b = {1.9, 0.8, 1.1, 0.1, -0.1, 4.4, 5.5, 1.6, 4.6, 3.4};
  std::vector<std::vector<double>> scores;
  for (std::size_t i = 0; i < a.size(); ++i) scores.push_back({a[i], b[i]});
  const RepeatedMeasuresAnova anova = repeated_measures_anova(scores);
  const TestResult t = paired_t_test(a, b);
  ASSERT_TRUE(anova.ok());
  EXPECT_NEAR(anova.f, t.statistic * t.statistic, 1e-9);
  EXPECT_NEAR(anova.p_value, t.p_value, 1e-12);
  EXPECT_DOUBLE_EQ(anova.epsilon_gg, 1.0);
}

TEST(AnalysisStatistics, RepeatedMeasuresAnovaSingleParticipantIsAStatement) {
  const RepeatedMeasuresAnova result = repeated_measures_anova({{1.0, 2.0, 3.0}});
  EXPECT_FALSE(result.ok());
  EXPECT_NE(result.unavailable.find("at least 2 participants"), std::string::npos);
}

TEST(AnalysisStatistics, MeanStandardErrorMedian) {
  const MeanSe summary = mean_and_standard_error({2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0});
  EXPECT_DOUBLE_EQ(summary.mean, 5.0);
  // Sample SD = sqrt(32 / 7).
  EXPECT_NEAR(*summary.standard_error, std::sqrt(32.0 / 7.0) / std::sqrt(8.0), 1e-15);
  EXPECT_FALSE(mean_and_standard_error({3.0}).standard_error.has_value());
  EXPECT_DOUBLE_EQ(median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_DOUBLE_EQ(median({4.0, 1.0, 2.0, 3.0}), 2.5);
}

}  // namespace
}  // namespace glarelab::analysis

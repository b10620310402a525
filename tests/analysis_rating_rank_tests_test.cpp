// The rank tests of the rating analysis (analysis/rank_tests.h) on hand-worked and published
// examples: every expected number below is derived in the comment beside it or quoted from the
// source named there, not from the code under test.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/rank_tests.h"

namespace glarelab::analysis {
namespace {

TEST(AnalysisRatingRankTests, MidranksAndTieGroups) {
  // 3 < 5 = 5 < 7 = 7 = 7: ranks 1, (2+3)/2, (4+5+6)/3.
  const std::vector<double> ranks = average_ranks({7, 5, 3, 7, 5, 7});
  const std::vector<double> expected = {5, 2.5, 1, 5, 2.5, 5};
  EXPECT_EQ(ranks, expected);
  const std::vector<std::size_t> groups = tie_group_sizes({7, 5, 3, 7, 5, 7});
  EXPECT_EQ(groups, (std::vector<std::size_t>{2, 3}));
}

// Hollander & Wolfe (1973), p. 29: Hamilton depression scale before (x) and after (y) a
// tranquilizer, nine patients (the example of R's wilcox.test). Differences x - y: 0.952,
// -0.147, 1.022, 0.43, 0.62, 0.59, 0.49, -0.08, 0.01; the two negative ones have |d| ranks 3 and
// 2, so R- = 5 and R+ = 45 - 5 = 40 (R reports V = 40, one-sided p = 0.01953). Under the null
// the 2^9 = 512 sign patterns are equally likely; rank sums <= 5 come from {}, {1}, {2}, {3},
// {1,2}, {4}, {1,3}, {5}, {1,4}, {2,3}: 10 subsets, so p = 2 * 10 / 512 = 0.0390625.
TEST(AnalysisRatingRankTests, SignedRankExactHollanderWolfe) {
  const std::vector<double> x = {1.83, 0.50, 1.62, 2.48, 1.68, 1.88, 1.55, 3.06, 1.30};
  const std::vector<double> y = {0.878, 0.647, 0.598, 2.05, 1.06, 1.29, 1.06, 3.14, 1.29};
  const WilcoxonSignedRank w = wilcoxon_signed_rank(x, y);
  ASSERT_TRUE(w.ok()) << w.unavailable;
  EXPECT_TRUE(w.exact);
  EXPECT_EQ(w.rank_sum_positive, 40.0);
  EXPECT_EQ(w.rank_sum_negative, 5.0);
  EXPECT_EQ(w.statistic, 5.0);
  EXPECT_DOUBLE_EQ(w.p_value, 20.0 / 512.0);
}

// Darwin's cross- and self-fertilized corn, height differences in eighths of an inch (Fisher
// 1935; the example of scipy.stats.wilcoxon): 15 distinct |d|, the negative ones -48 and -67
// ranked 10 and 14, so T = R- = 24. Exact two-sided p = 2 P(R+ <= 24 | n = 15) = 2 * 676 /
// 32768 = 0.041259765625 (SciPy's documented value). Normal: mean 15*16/4 = 60, variance
// 15*16*31/24 = 310, z = (24 - 60)/sqrt(310) = -2.04465; with the continuity correction
// z = (24 - 60 + 0.5)/sqrt(310) = -2.01625.
TEST(AnalysisRatingRankTests, SignedRankDarwinCornExactAndNormal) {
  const std::vector<double> d = {6, 8, 14, 16, 23, 24, 28, 29, 41, -48, 49, 56, 60, -67, 75};
  const std::vector<double> zero(d.size(), 0.0);
  const WilcoxonSignedRank exact = wilcoxon_signed_rank(d, zero);
  ASSERT_TRUE(exact.ok());
  EXPECT_TRUE(exact.exact);
  EXPECT_EQ(exact.statistic, 24.0);
  EXPECT_DOUBLE_EQ(exact.p_value, 0.041259765625);
  EXPECT_DOUBLE_EQ(exact.p_value, 2.0 * 676.0 / 32768.0);

  const WilcoxonSignedRank normal = wilcoxon_signed_rank(d, zero, WilcoxonMethod::normal);
  ASSERT_TRUE(normal.ok());
  EXPECT_FALSE(normal.exact);
  EXPECT_NEAR(normal.z, -36.0 / std::sqrt(310.0), 1e-12);
  EXPECT_NEAR(normal.p_value, std::erfc(36.0 / std::sqrt(310.0) / std::sqrt(2.0)), 1e-12);
  EXPECT_NEAR(normal.p_value, 0.04088813291185591, 1e-12);  // scipy.stats.wilcoxon(d, method='approx')

  const WilcoxonSignedRank corrected = wilcoxon_signed_rank(d, zero, WilcoxonMethod::normal, true);
  EXPECT_NEAR(corrected.z, -35.5 / std::sqrt(310.0), 1e-12);
  EXPECT_NEAR(corrected.p_value, std::erfc(35.5 / std::sqrt(310.0) / std::sqrt(2.0)), 1e-12);
}

// Ratings with a zero and tied differences: d = 1, 1, 1, -1, 2, 2, 0. The zero is discarded
// (n = 6); |d| = 1 (four times) share ranks 1-4 -> 2.5, |d| = 2 (twice) ranks 5-6 -> 5.5.
// R+ = 3 * 2.5 + 2 * 5.5 = 18.5, R- = 2.5 = T. Mean 6*7/4 = 10.5; variance (6*7*13 - (4^3 - 4 +
// 2^3 - 2)/2)/24 = (546 - 33)/24 = 21.375; z = -8/sqrt(21.375).
TEST(AnalysisRatingRankTests, SignedRankZerosAndTiesUseTheCorrectedNormal) {
  const std::vector<double> after = {5, 4, 6, 3, 6, 7, 4};
  const std::vector<double> before = {4, 3, 5, 4, 4, 5, 4};
  const WilcoxonSignedRank w = wilcoxon_signed_rank(after, before);
  ASSERT_TRUE(w.ok()) << w.unavailable;
  EXPECT_FALSE(w.exact);
  EXPECT_EQ(w.pairs, 7u);
  EXPECT_EQ(w.zero_differences, 1u);
  EXPECT_EQ(w.ranked, 6u);
  EXPECT_EQ(w.rank_sum_positive, 18.5);
  EXPECT_EQ(w.rank_sum_negative, 2.5);
  EXPECT_EQ(w.statistic, 2.5);
  const double z = -8.0 / std::sqrt(21.375);
  EXPECT_NEAR(w.z, z, 1e-12);
  EXPECT_NEAR(w.p_value, std::erfc(-z / std::sqrt(2.0)), 1e-12);
  EXPECT_NEAR(w.p_value, 0.08356564983357526, 1e-12);  // scipy.stats.wilcoxon([1, 1, 1, -1, 2, 2, 0])

  // The exact distribution assumes untied, non-zero differences: asked for, it is refused.
  const WilcoxonSignedRank exact = wilcoxon_signed_rank(after, before, WilcoxonMethod::exact);
  EXPECT_FALSE(exact.ok());
  EXPECT_NE(exact.unavailable.find("zero differences"), std::string::npos) << exact.unavailable;
  const WilcoxonSignedRank tied = wilcoxon_signed_rank({2, 3, 1}, {1, 2, 3}, WilcoxonMethod::exact);
  EXPECT_NE(tied.unavailable.find("tied"), std::string::npos) << tied.unavailable;
}

TEST(AnalysisRatingRankTests, SignedRankStatementsInsteadOfNaN) {
  EXPECT_EQ(wilcoxon_signed_rank({3, 4}, {3, 4}).unavailable, "every one of the 2 pairs is equal (all differences are zero)");
  EXPECT_EQ(wilcoxon_signed_rank({}, {}).unavailable, "no pairs");
  EXPECT_EQ(wilcoxon_signed_rank({1}, {1, 2}).unavailable, "unequal numbers of paired values");
  // R+ at the middle of its distribution (n = 3: R+ = 3 of 0..6) gives p = 1 exactly.
  const WilcoxonSignedRank middle = wilcoxon_signed_rank({1, 2, -3}, {0, 0, 0});
  ASSERT_TRUE(middle.ok());
  EXPECT_TRUE(middle.exact);
  EXPECT_EQ(middle.p_value, 1.0);
}

// Hollander & Wolfe (1973), p. 140f: times of 22 baseball players rounding first base by three
// methods (R's friedman.test example, "Friedman chi-squared = 11.143, df = 2, p-value =
// 0.003805"). Rows 7, 15, 17 and 22 have a tie of two, so C = 1 - 4 * 6 / (22 * 3 * 8).
TEST(AnalysisRatingRankTests, FriedmanRoundingFirstBase) {
  const std::vector<std::vector<double>> times = {
      {5.40, 5.50, 5.55}, {5.85, 5.70, 5.75}, {5.20, 5.60, 5.50}, {5.55, 5.50, 5.40}, {5.90, 5.85, 5.70},
      {5.45, 5.55, 5.60}, {5.40, 5.40, 5.35}, {5.45, 5.50, 5.35}, {5.25, 5.15, 5.00}, {5.85, 5.80, 5.70},
      {5.25, 5.20, 5.10}, {5.65, 5.55, 5.45}, {5.60, 5.35, 5.45}, {5.05, 5.00, 4.95}, {5.50, 5.50, 5.40},
      {5.45, 5.55, 5.50}, {5.55, 5.55, 5.35}, {5.45, 5.50, 5.55}, {5.50, 5.45, 5.25}, {5.65, 5.60, 5.40},
      {5.70, 5.65, 5.55}, {6.30, 6.30, 6.25}};
  const FriedmanTest f = friedman_test(times);
  ASSERT_TRUE(f.ok()) << f.unavailable;
  EXPECT_EQ(f.subjects, 22u);
  EXPECT_EQ(f.conditions, 3u);
  EXPECT_EQ(f.df, 2.0);
  EXPECT_NEAR(f.tie_correction, 1.0 - 24.0 / 528.0, 1e-15);
  EXPECT_NEAR(f.chi_square, 11.143, 5e-4);
  EXPECT_NEAR(f.p_value, 0.003805, 5e-7);
  // Two degrees of freedom: the chi-square upper tail is exp(-x/2).
  EXPECT_NEAR(f.p_value, std::exp(-f.chi_square / 2.0), 1e-14);
  EXPECT_NEAR(f.kendall_w, f.chi_square / 44.0, 1e-15);
}

// Four participants, three conditions, no ties. Rank rows 123, 132, 123, 213: column sums
// R = 5, 8, 11. chi2 = 12/(4*3*4) * (25 + 64 + 121) - 3*4*4 = 52.5 - 48 = 4.5; p = exp(-2.25).
// Kendall's W from its own definition: S = sum (R_j - n(k+1)/2)^2 = 9 + 0 + 9 = 18,
// W = 12 S / (n^2 (k^3 - k)) = 216 / 384 = 0.5625 = chi2 / (n (k - 1)).
TEST(AnalysisRatingRankTests, FriedmanAndKendallWByHand) {
  const FriedmanTest f = friedman_test({{1, 2, 3}, {1, 3, 2}, {2, 4, 6}, {5, 4, 7}});
  ASSERT_TRUE(f.ok()) << f.unavailable;
  EXPECT_EQ(f.tie_correction, 1.0);
  EXPECT_NEAR(f.chi_square, 4.5, 1e-13);
  EXPECT_NEAR(f.p_value, std::exp(-2.25), 1e-14);
  EXPECT_NEAR(f.kendall_w, 0.5625, 1e-14);
}

// The same with a tie: rows (1,1,2), (1,2,3), (2,1,3), (1,2,3) rank as (1.5,1.5,3), (1,2,3),
// (2,1,3), (1,2,3); R = 5.5, 6.5, 12; uncorrected 0.25 * 216.5 - 48 = 6.125; one tie of two:
// C = 1 - 6 / (4 * 3 * 8) = 0.9375; chi2 = 6.125 / 0.9375 = 6.5333. Kendall's W with its tie
// correction (Kendall & Babington Smith 1939): S = 2.5^2 + 1.5^2 + 4^2 = 24.5,
// W = 12 S / (n^2 (k^3 - k) - n sum(t^3 - t)) = 294 / (384 - 24) = 0.81667 = chi2 / (n (k - 1)).
TEST(AnalysisRatingRankTests, FriedmanTieCorrectionByHand) {
  const FriedmanTest f = friedman_test({{1, 1, 2}, {1, 2, 3}, {2, 1, 3}, {1, 2, 3}});
  ASSERT_TRUE(f.ok()) << f.unavailable;
  EXPECT_NEAR(f.tie_correction, 0.9375, 1e-15);
  EXPECT_NEAR(f.chi_square, 6.125 / 0.9375, 1e-13);
  EXPECT_NEAR(f.p_value, std::exp(-6.125 / 0.9375 / 2.0), 1e-14);
  EXPECT_NEAR(f.kendall_w, 294.0 / 360.0, 1e-14);
}

TEST(AnalysisRatingRankTests, FriedmanStatementsInsteadOfNaN) {
  EXPECT_NE(friedman_test({{1, 2}, {2, 1}}).unavailable.find("at least 3 conditions"), std::string::npos);
  EXPECT_NE(friedman_test({{1, 2, 3}}).unavailable.find("at least 2 participants"), std::string::npos);
  EXPECT_EQ(friedman_test({{4, 4, 4}, {2, 2, 2}}).unavailable,
            "every participant gave every condition the same score (no ranks to compare)");
  EXPECT_EQ(friedman_test({{1, 2, 3}, {1, 2}}).unavailable, "incomplete rows");
  // Perfect agreement: W = 1; no difference between the rank sums: chi2 = 0, p = 1.
  EXPECT_NEAR(friedman_test({{1, 2, 3}, {4, 5, 6}, {0, 3, 9}}).kendall_w, 1.0, 1e-14);
  const FriedmanTest none = friedman_test({{1, 2, 3}, {3, 1, 2}, {2, 3, 1}});
  EXPECT_NEAR(none.chi_square, 0.0, 1e-14);
  EXPECT_NEAR(none.p_value, 1.0, 1e-14);
}

}  // namespace
}  // namespace glarelab::analysis

#pragma once
// Post-hoc pairwise comparisons after a significant Friedman test of ratings: the Wilcoxon
// signed-rank test (analysis/rank_tests.h, WilcoxonMethod::automatic) on every pair of
// conditions, with Holm's (1979) step-down adjustment of the p-values for the number of pairs.
// Which pairs differ is what the Friedman test alone does not say (e.g. the real lamp against each
// simulation in Luidolt 2020's study, examples/luidolt_ratings.toml). Checked against
// scipy.stats.wilcoxon per pair and Holm's adjustment by hand (tests/analysis_rating_post_hoc_test.cpp).
#include <string>
#include <vector>

#include "analysis/rank_tests.h"

namespace glarelab::analysis {

// Holm's adjusted p-values, in the order given: with p sorted ascending p_(1) <= ... <= p_(m),
// adjusted p_(i) = min(1, max_{j <= i} (m - j + 1) p_(j)). Rejecting where the adjusted p is at
// most alpha controls the family-wise error rate at alpha. Equal p-values keep their given order.
std::vector<double> holm_adjusted_p(const std::vector<double>& p_values);

struct RatingPairTest {
  std::string first, second;   // conditions; the differences are first - second
  WilcoxonSignedRank wilcoxon;
  double p_holm = 1.0;         // Holm-adjusted over the pairs that have a result
};

// The significance level at which a Friedman test opens the pairwise comparisons.
inline constexpr double kPostHocAlpha = 0.05;

// Every pair (i < j, in the order of `conditions`) of the columns of scores[participant][condition]
// when `friedman_p` <= kPostHocAlpha; empty otherwise. Pairs without a result (every difference
// zero) keep p_holm 1 and do not count towards the adjustment.
std::vector<RatingPairTest> rating_post_hoc(const std::vector<std::string>& conditions,
                                            const std::vector<std::vector<double>>& scores, double friedman_p);

}  // namespace glarelab::analysis

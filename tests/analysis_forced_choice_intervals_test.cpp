// Forced-choice shares with Clopper-Pearson intervals and the chi-square left out at small n
// (analysis/statistics.h, analysis/forced_choice_analysis.h).
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/forced_choice_analysis.h"
#include "analysis/statistics.h"

namespace glarelab::analysis {
namespace {

// P(X >= k) and P(X <= k) for X ~ Binomial(n, p), summed term by term (no beta function).
double upper_tail(long k, long n, double p) {
  double sum = 0.0;
  for (long x = k; x <= n; ++x) sum += std::exp(std::lgamma(static_cast<double>(n) + 1.0) - std::lgamma(static_cast<double>(x) + 1.0) -
                                                std::lgamma(static_cast<double>(n - x) + 1.0)) *
                                       std::pow(p, static_cast<double>(x)) * std::pow(1.0 - p, static_cast<double>(n - x));
  return sum;
}
double lower_tail(long k, long n, double p) { return 1.0 - (k + 1 <= n ? upper_tail(k + 1, n, p) : 0.0); }

// R's binom.test(7, 20) prints the 95 percent confidence interval 0.1539092 0.5921885.
TEST(AnalysisClopperPearson, RBinomTestExample) {
  const ProportionInterval ci = clopper_pearson_interval(7, 20);
  EXPECT_NEAR(ci.low, 0.1539092, 5e-8);
  EXPECT_NEAR(ci.high, 0.5921885, 5e-8);
}

// The definition: each end is where the tail beyond the observed count has probability 0.025.
// 15 of 16 correct (a scored 2-AFC as the issue reports it) and 2 of 2.
TEST(AnalysisClopperPearson, EndsHoldTheTailProbabilities) {
  for (const auto& [k, n] : {std::pair<long, long>{15, 16}, {2, 2}, {3, 8}, {1, 4}}) {
    const ProportionInterval ci = clopper_pearson_interval(k, n);
    EXPECT_NEAR(upper_tail(k, n, ci.low), 0.025, 1e-10) << k << "/" << n;
    if (k < n) EXPECT_NEAR(lower_tail(k, n, ci.high), 0.025, 1e-10) << k << "/" << n;
    else EXPECT_EQ(ci.high, 1.0);
    EXPECT_LT(ci.low, static_cast<double>(k) / static_cast<double>(n));
  }
}

// At 0 and n the one open end has a closed form: (1 - p)^n = 0.025, p^n = 0.025.
TEST(AnalysisClopperPearson, AllOrNoneClosedForm) {
  const ProportionInterval none = clopper_pearson_interval(0, 10);
  EXPECT_EQ(none.low, 0.0);
  EXPECT_NEAR(none.high, 1.0 - std::pow(0.025, 0.1), 1e-12);
  const ProportionInterval all = clopper_pearson_interval(10, 10);
  EXPECT_NEAR(all.low, std::pow(0.025, 0.1), 1e-12);
  EXPECT_EQ(all.high, 1.0);
  // Two answers, both one way: far from the normal approximation's zero width.
  EXPECT_NEAR(clopper_pearson_interval(2, 2).low, std::sqrt(0.025), 1e-12);
}

LoadedTrial choice(const std::string& left, const std::string& right, const std::string& response) {
  LoadedTrial t;
  t.record.procedure = "forced_choice";
  t.record.response = response;
  t.condition = {{"name", "pair"}, {"left", left}, {"right", right}};
  return t;
}

// Four answers: the exact binomial test and the interval, no chi-square; ten: the chi-square too.
TEST(AnalysisClopperPearson, ChiSquareOnlyFromTenAnswers) {
  for (const long n : {4L, 10L}) {
    LoadedData data;
    data.sessions.emplace_back();
    for (long i = 0; i < n; ++i) {
      data.sessions[0].trials.push_back(choice("dynamic", "static", i == 0 ? "right" : "left"));
      data.sessions[0].trials.back().record.correct = i == 0 ? 0 : 1;  // scored: "dynamic" was right
    }
    const ForcedChoiceAnalysis analysis = analyse_forced_choice(data);
    ASSERT_EQ(analysis.groups.size(), 1u);
    const PairPreference& p = analysis.groups[0];
    EXPECT_EQ(p.chose_a, n - 1);
    EXPECT_TRUE(p.binomial.ok());
    EXPECT_EQ(p.chi_square.ok(), n >= 10) << n;
    const ProportionInterval expected = clopper_pearson_interval(n - 1, n);
    EXPECT_EQ(p.share_a_interval.low, expected.low);
    EXPECT_EQ(p.share_a_interval.high, expected.high);
    // Percent correct of the scored trials: n - 1 of n, the same interval, the exact test's p
    // 2 (n + 1) / 2^n (outcomes 0, 1, n - 1, n each at most as likely).
    ASSERT_EQ(analysis.scored.size(), 1u);
    EXPECT_EQ(analysis.scored[0].correct, n - 1);
    EXPECT_EQ(analysis.scored[0].trials, n);
    EXPECT_EQ(analysis.scored[0].interval.low, expected.low);
    EXPECT_NEAR(analysis.scored[0].binomial.p_value, 2.0 * static_cast<double>(n + 1) / std::pow(2.0, static_cast<double>(n)), 1e-12);
  }
}

}  // namespace
}  // namespace glarelab::analysis

// The PSE posterior of the graded forced-choice analysis (analysis/pse_posterior.h) on cases whose
// answers are known without it: a design and answers symmetric about 0 (so the posterior of the PSE
// is symmetric: median 0, interval ends opposite), answers that separate perfectly (no maximum-
// likelihood fit, but an interval around the gap), identical groups (a shift interval symmetric
// about 0) and inputs with no posterior.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "analysis/pse_posterior.h"

namespace glarelab::analysis {
namespace {

TEST(PsePosterior, SymmetricAnswersGiveASymmetricPosterior) {
  // P(naming b) 1/8, 2/8, 4/8, 6/8, 7/8 at -2 .. 2: mirrored in x -> -x with k -> n - k, as are the
  // priors (set from the levels) and the grid, so the PSE's posterior is symmetric about 0.
  const std::vector<StimulusLevel> levels = {{-2.0, 8, 1}, {-1.0, 8, 2}, {0.0, 8, 4}, {1.0, 8, 6}, {2.0, 8, 7}};
  const std::optional<PsePosterior> posterior = pse_posterior(levels);
  ASSERT_TRUE(posterior);
  EXPECT_NEAR(posterior->median, 0.0, 1e-9);
  EXPECT_NEAR(posterior->credible.low, -posterior->credible.high, 1e-9);
  EXPECT_LT(posterior->credible.low, -0.3);  // 40 answers do not pin the PSE down to a grid step
  EXPECT_GT(posterior->credible.low, -2.0);
  EXPECT_NEAR(std::accumulate(posterior->probability.begin(), posterior->probability.end(), 0.0), 1.0, 1e-12);
  // The grid spans half the tested range beyond either end.
  EXPECT_DOUBLE_EQ(posterior->mu.front(), -4.0);
  EXPECT_DOUBLE_EQ(posterior->mu.back(), 4.0);
  // The median curve crosses 1/2 at the median and rises through the answers.
  EXPECT_NEAR(posterior->probability_at(posterior->median), 0.5, 1e-12);
  EXPECT_LT(posterior->probability_at(-1.0), 0.35);
  EXPECT_GT(posterior->probability_at(1.0), 0.65);
}

TEST(PsePosterior, AnswersThatSeparatePerfectlyStillHaveAnIntervalAroundTheGap) {
  // None naming b up to 0, all from 1 on: any PSE in (0, 1) with a steep enough slope fits them
  // perfectly, so the likelihood has no maximum, but the width prior keeps the posterior proper.
  const std::vector<StimulusLevel> levels = {{-1.0, 4, 0}, {0.0, 4, 0}, {1.0, 4, 4}, {2.0, 4, 4}};
  const std::optional<PsePosterior> posterior = pse_posterior(levels);
  ASSERT_TRUE(posterior);
  EXPECT_NEAR(posterior->median, 0.5, 1e-9);  // the gap's middle, by the same symmetry
  EXPECT_NEAR(posterior->credible.low, 1.0 - posterior->credible.high, 1e-9);
  EXPECT_LT(posterior->credible.low, 0.1);  // nearly the whole gap, where every PSE fits
  EXPECT_GT(posterior->credible.high, 0.9);
  EXPECT_GT(posterior->credible.low, -1.0);
  EXPECT_LT(posterior->credible.high, 2.0);
}

TEST(PsePosterior, IdenticalGroupsGiveAShiftIntervalSymmetricAboutZero) {
  const std::vector<StimulusLevel> levels = {{-0.1, 6, 1}, {0.0, 6, 3}, {0.1, 6, 4}, {0.2, 6, 6}};
  const std::optional<PsePosterior> a = pse_posterior(levels), b = pse_posterior(levels);
  ASSERT_TRUE(a && b);
  const Interval shift = pse_shift_credible_interval(*a, *b);
  EXPECT_NEAR(shift.low, -shift.high, 1e-9);
  EXPECT_LT(shift.low, 0.0);
  // Two independent PSEs: the difference is wider than either alone.
  EXPECT_GT(shift.high - shift.low, a->credible.high - a->credible.low);
  // Moving every level of b by 0.05 moves the shift interval by 0.05 (the grids move with them).
  std::vector<StimulusLevel> moved = levels;
  for (StimulusLevel& level : moved) level.intensity += 0.05;
  const Interval moved_shift = pse_shift_credible_interval(*a, *pse_posterior(moved));
  EXPECT_NEAR(moved_shift.low, shift.low + 0.05, 1e-9);
  EXPECT_NEAR(moved_shift.high, shift.high + 0.05, 1e-9);
}

TEST(PsePosterior, NoPosteriorWithoutTwoLevelsOrAnswers) {
  EXPECT_FALSE(pse_posterior({}));
  EXPECT_FALSE(pse_posterior({{0.5, 10, 5}}));
  EXPECT_FALSE(pse_posterior({{0.5, 10, 5}, {0.5, 4, 2}}));  // one level, stored twice
  EXPECT_FALSE(pse_posterior({{0.0, 0, 0}, {1.0, 0, 0}}));
}

}  // namespace
}  // namespace glarelab::analysis

// Maximum-likelihood psychometric fits: a published maximum-likelihood example, recovery of a
// simulated observer's parameters, and the cases where a slope cannot be identified.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/psychometric_fit.h"
#include "core/random.h"

namespace glarelab::analysis {
namespace {

// Bliss (1935) beetle mortality after 5 h exposure to gaseous carbon disulphide, as tabulated in
// Dobson & Barnett, An Introduction to Generalized Linear Models (3rd ed., Table 7.2): log10 dose,
// beetles, killed.
std::vector<StimulusLevel> bliss_beetles() {
  return {{1.6907, 59, 6},  {1.7242, 60, 13}, {1.7552, 62, 18}, {1.7842, 56, 28},
          {1.8113, 63, 52}, {1.8369, 59, 53}, {1.8610, 62, 61}, {1.8839, 60, 60}};
}

TEST(AnalysisPsychometric, LogisticMatchesPublishedBlissFit) {
  // With guess 0 and no lapse the logistic psychometric function is the logit model. Dobson &
  // Barnett, Table 7.3: b1 = -60.72, b2 = 34.27, deviance D = 11.23. Threshold = -b1 / b2.
  PsychometricFitOptions options;
  options.shape = PsychometricShape::logistic;
  options.guess_rate = 0.0;
  options.lapse_max = 0.0;
  options.bootstrap_samples = 0;
  const PsychometricFit fit = fit_psychometric(bliss_beetles(), options);
  ASSERT_TRUE(fit.ok()) << fit.unavailable;
  EXPECT_NEAR(fit.slope, 34.27, 0.01 * 34.27);
  EXPECT_NEAR(fit.threshold, 60.72 / 34.27, 0.01 * 60.72 / 34.27);
  EXPECT_NEAR(-fit.slope * fit.threshold, -60.72, 0.01 * 60.72);
  EXPECT_NEAR(fit.deviance, 11.23, 0.01 * 11.23);
  EXPECT_EQ(fit.deviance_df, 6);
}

TEST(AnalysisPsychometric, CumulativeNormalMatchesPublishedBlissFit) {
  // Probit model, Dobson & Barnett Table 7.3: b1 = -34.94, b2 = 19.73, D = 10.12.
  PsychometricFitOptions options;
  options.shape = PsychometricShape::cumulative_normal;
  options.guess_rate = 0.0;
  options.lapse_max = 0.0;
  options.bootstrap_samples = 0;
  const PsychometricFit fit = fit_psychometric(bliss_beetles(), options);
  ASSERT_TRUE(fit.ok()) << fit.unavailable;
  EXPECT_NEAR(fit.slope, 19.73, 0.01 * 19.73);
  EXPECT_NEAR(-fit.slope * fit.threshold, -34.94, 0.01 * 34.94);
  EXPECT_NEAR(fit.deviance, 10.12, 0.01 * 10.12);
}

// A simulated 2AFC observer: each trial correct with probability psi(x) from the given
// parameters, drawn from its own seeded stream (independent of the bootstrap stream).
std::vector<StimulusLevel> simulate(PsychometricShape shape, double alpha, double beta, double lapse,
                                    const std::vector<double>& intensities, long trials_per_level, std::uint64_t seed) {
  const CounterRandom random(seed, RandomStream::observer);
  std::vector<StimulusLevel> levels;
  for (std::size_t i = 0; i < intensities.size(); ++i) {
    StimulusLevel level{intensities[i], trials_per_level, 0};
    const double psi = psychometric_probability(shape, intensities[i], alpha, beta, 0.5, lapse);
    for (long t = 0; t < trials_per_level; ++t) level.correct += random.uniform(i, static_cast<std::uint32_t>(t)) < psi;
    levels.push_back(level);
  }
  return levels;
}

void expect_recovery(PsychometricShape shape, double alpha, double beta, const std::vector<double>& intensities) {
  constexpr int kRuns = 40;
  int threshold_inside = 0;
  int slope_inside = 0;
  for (int run = 0; run < kRuns; ++run) {
    const auto levels = simulate(shape, alpha, beta, 0.02, intensities, 100, 1000 + static_cast<std::uint64_t>(run));
    PsychometricFitOptions options;
    options.shape = shape;
    options.guess_rate = 0.5;
    options.bootstrap_samples = 200;
    options.seed = 77 + static_cast<std::uint64_t>(run);
    const PsychometricFit fit = fit_psychometric(levels, options);
    ASSERT_TRUE(fit.ok()) << fit.unavailable;
    ASSERT_TRUE(fit.threshold_ci && fit.slope_ci);
    threshold_inside += alpha >= fit.threshold_ci->low && alpha <= fit.threshold_ci->high;
    slope_inside += beta >= fit.slope_ci->low && beta <= fit.slope_ci->high;
  }
  EXPECT_GE(threshold_inside, 36) << shape_name(shape) << ": threshold inside its 95% interval in " << threshold_inside
                                  << " of " << kRuns;
  EXPECT_GE(slope_inside, 36) << shape_name(shape) << ": slope inside its 95% interval in " << slope_inside << " of "
                              << kRuns;
}

TEST(AnalysisPsychometric, LogisticRecoversSimulatedObserver) {
  expect_recovery(PsychometricShape::logistic, 1.0, 4.0, {0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75});
}

TEST(AnalysisPsychometric, WeibullRecoversSimulatedObserver) {
  expect_recovery(PsychometricShape::weibull, 2.0, 3.0, {0.75, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0});
}

TEST(AnalysisPsychometric, CumulativeNormalRecoversSimulatedObserver) {
  expect_recovery(PsychometricShape::cumulative_normal, 0.0, 1.5, {-1.5, -1.0, -0.5, 0.0, 0.5, 1.0, 1.5});
}

TEST(AnalysisPsychometric, AllCorrectIsNotIdentifiable) {
  PsychometricFitOptions options;
  const PsychometricFit fit = fit_psychometric({{1.0, 20, 20}, {2.0, 20, 20}}, options);
  EXPECT_FALSE(fit.ok());
  EXPECT_EQ(fit.unavailable, "slope not identifiable: all 40 responses correct");
}

TEST(AnalysisPsychometric, PerfectSeparationRunsToTheBoundAndIsReported) {
  // Chance below 1.5, always right above: the likelihood keeps rising as the slope steepens.
  PsychometricFitOptions options;
  options.lapse_max = 0.0;
  const PsychometricFit fit = fit_psychometric({{1.0, 40, 20}, {2.0, 40, 40}, {3.0, 40, 40}}, options);
  EXPECT_FALSE(fit.ok());
  EXPECT_EQ(fit.unavailable,
            "slope not identifiable: all 80 responses at intensity >= 2 correct, at or below chance below it (perfect "
            "separation)");
}

TEST(AnalysisPsychometric, SingleLevelAndNegativeWeibullAreStatements) {
  PsychometricFitOptions options;
  EXPECT_NE(fit_psychometric({{1.0, 10, 7}}, options).unavailable.find("only one intensity"), std::string::npos);
  options.shape = PsychometricShape::weibull;
  EXPECT_NE(fit_psychometric({{-1.0, 10, 5}, {1.0, 10, 8}}, options).unavailable.find("positive"), std::string::npos);
}

}  // namespace
}  // namespace glarelab::analysis

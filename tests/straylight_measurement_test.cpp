// The compensation-comparison straylight measurement (protocols/straylight_model.h) against closed
// forms and the acceptance: simulated observers of known straylight are measured with
// 25 answers over 40 seeds, and an eye scattering exactly as CIE 146:2002 (age 25, pigmentation
// 0.5) is measured at the s that function gives over the ring, integrated here from the standard's
// formula itself.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "glare/analytic/cie_glare_spread.h"
#include "glare/analytic/ring_straylight.h"
#include "protocols/straylight_model.h"
#include "protocols/straylight_observer.h"

namespace glarelab {
namespace {

constexpr double kInnerDeg = 5.0;
constexpr double kOuterDeg = 10.0;
constexpr double kRingCdM2 = 100.0;
constexpr double kGlowCdM2 = 0.02;  // the display's own stray light on the field, subtracted

// One measurement as the procedure runs it: each level in straylight units becomes compensation
// light k s_c L_ring plus the display's glow (which flickers with the ring, so adding it to the
// compensation removes it from the compensated half's flicker).
StraylightEstimate measure(const StraylightObserver& observer, std::uint64_t seed) {
  const StraylightSchedule schedule;
  const StraylightPsychometric model;
  const double k = ring_straylight_constant(kInnerDeg, kOuterDeg);
  std::vector<StraylightAnswer> answers;
  while (static_cast<int>(answers.size()) < schedule.answers) {
    const double level = next_log_compensation(schedule, answers, model, seed);
    const StraylightStimulus stimulus{kRingCdM2, kGlowCdM2, k * std::pow(10.0, level) * kRingCdM2 + kGlowCdM2};
    answers.push_back({level, observer.compensated_stronger(stimulus, answers.size())});
  }
  return estimate_straylight(answers, model);
}

struct Spread {
  double mean = 0.0, sd = 0.0, mean_esd = 0.0, mean_likelihood_sd = 0.0;
};

Spread measure_seeds(const StraylightObserverEye& eye, int seeds) {
  std::vector<double> values;
  Spread spread;
  for (int seed = 1; seed <= seeds; ++seed) {
    const StraylightEstimate estimate = measure(StraylightObserver(eye, 1000 + seed), 1000 + seed);
    values.push_back(estimate.log_s);
    spread.mean += estimate.log_s / seeds;
    spread.mean_esd += estimate.esd_log10 / seeds;
    spread.mean_likelihood_sd += estimate.likelihood_sd_log10 / seeds;
  }
  for (double v : values) spread.sd += (v - spread.mean) * (v - spread.mean);
  spread.sd = std::sqrt(spread.sd / (seeds - 1));
  return spread;
}

TEST(StraylightModel, RingConstantIsTheUniformRingsSolidAngleIntegral) {
  // The value for 5-10 degrees, and 2 pi (pi/180)^2 ln 2 written out.
  EXPECT_NEAR(ring_straylight_constant(5.0, 10.0), 1.327e-3, 0.0005e-3);
  EXPECT_NEAR(ring_straylight_constant(5.0, 10.0), 2.0 * std::numbers::pi * std::pow(std::numbers::pi / 180.0, 2) * std::log(2.0), 1e-15);
  // A ring twice as wide in log angle collects twice the light.
  EXPECT_NEAR(ring_straylight_constant(2.5, 10.0), 2.0 * ring_straylight_constant(5.0, 10.0), 1e-15);
  EXPECT_THROW(ring_straylight_constant(10.0, 5.0), std::invalid_argument);
}

TEST(StraylightModel, AgeNormAtItsKnownPoints) {
  EXPECT_NEAR(straylight_age_norm_log10(0.0), 0.87, 1e-12);
  EXPECT_NEAR(straylight_age_norm_log10(65.0), 0.87 + std::log10(2.0), 1e-12);
  EXPECT_NEAR(straylight_age_norm_log10(80.0), 0.87 + std::log10(1.0 + std::pow(80.0 / 65.0, 4)), 1e-12);
}

TEST(StraylightModel, PsychometricPointsOfTheFlickerAmplitudes) {
  const StraylightPsychometric model{0.15, 0.04};
  // s_c = 2 s: both halves flicker with amplitude s.
  EXPECT_NEAR(probability_compensated_stronger(1.2, 1.2 + std::log10(2.0), model), 0.5, 1e-12);
  // s_c = s: the compensated half is still, only lapses choose it.
  EXPECT_NEAR(probability_compensated_stronger(1.2, 1.2, model), 0.02, 1e-12);
  // s_c = 3 s: amplitude 2 s against s, log10 2 / 0.15 standard deviations.
  const double expected = 0.02 + 0.96 * 0.5 * std::erfc(-std::log10(2.0) / 0.15 / std::numbers::sqrt2);
  EXPECT_NEAR(probability_compensated_stronger(1.2, 1.2 + std::log10(3.0), model), expected, 1e-12);
}

TEST(StraylightModel, EstimateOfAnswersAtTheirExpectedRatesPeaksAtTheTruth) {
  // Answers in the exact proportions the model predicts at each level (many per level) make the
  // likelihood peak at the true value; its ESD shrinks as 1/sqrt(answers).
  const StraylightPsychometric model;
  const double truth = 1.3;
  std::vector<StraylightAnswer> answers;
  for (int level = -10; level <= 10; ++level) {
    const double x = truth + std::log10(2.0) + 0.03 * level;
    const int yes = static_cast<int>(std::lround(200.0 * probability_compensated_stronger(truth, x, model)));
    for (int i = 0; i < 200; ++i) answers.push_back({x, i < yes});
  }
  const StraylightEstimate estimate = estimate_straylight(answers, model);
  EXPECT_NEAR(estimate.log_s, truth, 0.003);
  EXPECT_LT(estimate.esd_log10, 0.01);
  EXPECT_FALSE(estimate.unreliable);
  double total = 0.0;
  for (double p : estimate.likelihood.normalised) total += p;
  EXPECT_NEAR(total, 1.0, 1e-12);
}

TEST(StraylightModel, FewAnswersAreFlaggedUnreliable) {
  const StraylightEstimate estimate = estimate_straylight({{1.5, true}, {1.3, false}}, StraylightPsychometric{});
  EXPECT_GT(estimate.esd_log10, kStraylightUnreliableEsdLog10);
  EXPECT_TRUE(estimate.unreliable);
}

// Acceptance 1: 0.9, 1.2 and 1.5, 40 seeds, 25 answers: SD <= 0.07 (Franssen 2006's
// repeatability), mean within 0.02, and the ESD the seeds' SD within 30 %.
TEST(StraylightMeasurement, RecoversSimulatedObserversStraylight) {
  const double k = ring_straylight_constant(kInnerDeg, kOuterDeg);
  for (const double truth : {0.9, 1.2, 1.5}) {
    StraylightObserverEye eye;
    eye.ring_veil_fraction = k * std::pow(10.0, truth);  // the same s at every angle of the ring
    const Spread spread = measure_seeds(eye, 40);
    SCOPED_TRACE(testing::Message() << "log s " << truth << ": mean " << spread.mean << " SD " << spread.sd
                                    << " mean ESD " << spread.mean_esd);
    EXPECT_LE(spread.sd, 0.07);
    EXPECT_NEAR(spread.mean, truth, 0.02);
    // The issue asks for ESD within 30 % of the seeds' SD; measured: within it at 0.9 and 1.5, 43 %
    // above it at 1.2 (docs/STRAYLIGHT.md). Held here: the ESD never understates the scatter by more
    // than 30 % and overstates it by less than half.
    EXPECT_GE(spread.mean_esd / spread.sd, 0.7);
    EXPECT_LE(spread.mean_esd / spread.sd, 1.5);
    // The ESD (the likelihood's half-width at e^-1/2 of its peak) agrees within the 30 %
    // (docs/STRAYLIGHT.md, "The estimate": 0.80 to 0.94 here; the SD of the whole likelihood, its
    // tails included, was 1.43 at 1.2).
    EXPECT_NEAR(spread.mean_esd / spread.sd, 1.0, 0.3);
    std::printf("log s %.2f: mean %.4f SD %.4f mean ESD %.4f (ESD / SD %.2f; likelihood SD %.4f, / SD %.2f)\n", truth,
                spread.mean, spread.sd, spread.mean_esd, spread.mean_esd / spread.sd, spread.mean_likelihood_sd,
                spread.mean_likelihood_sd / spread.sd);
  }
}

// Acceptance 2: the eye scatters exactly as CIE 146 (age 25, pigmentation 0.5); the ring
// measures the log-angle mean of s(theta) = theta^2 GSF(theta) over 5-10 degrees, which this
// test integrates from the standard's formula written out here (midpoint rule in ln theta).
TEST(StraylightMeasurement, MeasuresTheCieEyesStraylightOverTheRing) {
  const double age = 25.0, pigmentation = 0.5;
  const auto gsf = [&](double t) {
    return 10.0 / std::pow(t, 3) + (5.0 / (t * t) + 0.1 * pigmentation / t) * (1.0 + std::pow(age / 62.5, 4)) +
           0.0025 * pigmentation;
  };
  const int n = 20000;
  const double du = std::log(kOuterDeg / kInnerDeg) / n;
  double integral = 0.0;
  for (int i = 0; i < n; ++i) {
    const double t = kInnerDeg * std::exp((i + 0.5) * du);
    integral += t * t * gsf(t) * du;
  }
  const double ring_log_s = std::log10(integral / std::log(kOuterDeg / kInnerDeg));
  EXPECT_NEAR(ring_log_s, 0.84, 0.01);  // the "about 0.84"

  StraylightObserverEye eye;
  eye.ring_veil_fraction = cie146_ring_veil_fraction(kInnerDeg, kOuterDeg, cie146_age_factor(age), pigmentation);
  EXPECT_NEAR(std::log10(eye.ring_veil_fraction / ring_straylight_constant(kInnerDeg, kOuterDeg)), ring_log_s, 1e-6);
  const Spread spread = measure_seeds(eye, 40);
  SCOPED_TRACE(testing::Message() << "ring log s " << ring_log_s << ": mean " << spread.mean << " SD " << spread.sd);
  EXPECT_NEAR(spread.mean, ring_log_s, 0.03);
  std::printf("CIE age 25, pigmentation 0.5: ring log s %.4f, measured mean %.4f SD %.4f\n", ring_log_s, spread.mean, spread.sd);
}

TEST(StraylightMeasurement, MeasuredStraylightIsTheCieEyeWithThatWideAngleFactor) {
  // Round trip: the factor for the CIE eye's own s at 7 degrees is its age factor, for three ages.
  for (const double age : {25.0, 50.0, 80.0}) {
    const double t = kStraylightReferenceAngleDeg;
    const double log_s = std::log10(t * t * cie146_glare_spread_per_sr(t, age, 0.5));
    EXPECT_NEAR(cie146_factor_for_straylight(log_s, t, 0.5), 1.0 + std::pow(age / 62.5, 4), 1e-12) << age;
  }
  // The chosen value is met at 7 degrees: GSF(7) = 10^1.4 / 49.
  const double factor = cie146_factor_for_straylight(1.4, 7.0, 0.5);
  EXPECT_NEAR(cie146_glare_spread_for_factor_per_sr(7.0, factor, 0.5), std::pow(10.0, 1.4) / 49.0, 1e-12);
  EXPECT_NEAR(cie146_straylight_log10(7.0, factor, 0.5), 1.4, 1e-12);
  // Below the function's age-independent terms there is no such eye.
  EXPECT_THROW(cie146_factor_for_straylight(0.1, 7.0, 0.5), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab

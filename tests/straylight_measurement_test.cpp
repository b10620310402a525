// The compensation-comparison straylight measurement (protocols/straylight_model.h) against closed
// forms and the acceptance: simulated observers of known straylight are measured, through
// the procedure as a session runs it, with 25 answers over 40 seeds, and an eye scattering exactly as CIE 146:2002 (age 25, pigmentation
// 0.5) is measured at the s that function gives over the ring, integrated here from the standard's
// formula itself.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <vector>

#include "glare/analytic/cie_glare_spread.h"
#include "glare/analytic/ring_straylight.h"
#include "protocols/straylight_model.h"
#include "protocols/straylight_observer.h"
#include "protocols/straylight_procedure.h"

namespace glarelab {
namespace {

constexpr double kInnerDeg = 5.0;
constexpr double kOuterDeg = 10.0;
constexpr double kRingCdM2 = 100.0;
// The display's own stray light on the field (0.02 / (k 100) = 0.15 deg^2/sr): the participant
// sees it flicker with the ring, the procedure's estimate subtracts it.
constexpr double kGlowCdM2 = 0.02;

// One measurement as a session runs it: the procedure plans each level (clamped to the
// compensation range, on the 0.02 grid) and the compensated side, the simulated participant sees
// the ring, the glow and the compensation light L_c = k s_c L_ring on the plan's side and names a
// half, and the procedure scores and estimates from the answers.
StraylightEstimate measure(const StraylightObserverEye& eye, std::uint64_t seed) {
  StraylightSpec spec;
  spec.eye = "right";
  spec.ring_luminance_cd_m2 = kRingCdM2;
  spec.display_glow_cd_m2 = kGlowCdM2;
  StraylightProcedure procedure(spec, seed);
  const std::unique_ptr<Observer> participant = make_straylight_participant(eye, seed, 0.8);
  while (!procedure.finished()) {
    const TrialPlan plan = procedure.next_trial();
    procedure.record_response(plan, participant->respond(plan));
  }
  EXPECT_EQ(procedure.answers().size(), 25u);
  return procedure.estimate();
}

struct Spread {
  double mean = 0.0, sd = 0.0, mean_esd = 0.0, mean_likelihood_sd = 0.0;
};

Spread measure_seeds(const StraylightObserverEye& eye, int seeds) {
  std::vector<double> values;
  Spread spread;
  for (int seed = 1; seed <= seeds; ++seed) {
    const StraylightEstimate estimate = measure(eye, static_cast<std::uint64_t>(1000 + seed));
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
// repeatability), mean within 0.02, and the ESD the seeds' SD within 30 %. Measured (seeds
// 1001-1040): means 0.906, 1.212, 1.510; SDs 0.044, 0.040, 0.043; ESD / SD 0.88, 0.90, 0.81.
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
    // The ESD (the likelihood's half-width at e^-1/2 of its peak) against the seeds' SD, within
    // the 30 % (docs/STRAYLIGHT.md, "The estimate").
    EXPECT_NEAR(spread.mean_esd / spread.sd, 1.0, 0.3);
    std::printf("log s %.2f: mean %.4f SD %.4f mean ESD %.4f (ESD / SD %.2f; likelihood SD %.4f, / SD %.2f)\n", truth,
                spread.mean, spread.sd, spread.mean_esd, spread.mean_esd / spread.sd, spread.mean_likelihood_sd,
                spread.mean_likelihood_sd / spread.sd);
  }
}

// Acceptance 2: the eye scatters exactly as CIE 146 (age 25, pigmentation 0.5); the ring
// measures the log-angle mean of s(theta) = theta^2 GSF(theta) over 5-10 degrees, which this
// test integrates from the standard's formula written out here (midpoint rule in ln theta).
// One measurement scatters with SD about 0.043, so the acceptance's 0.03 is asserted on the mean
// of 100 (standard error about 0.004): a bias of the method, not one measurement's luck. Measured:
// 0.847 against 0.846 (over 400 seeds 0.850; docs/STRAYLIGHT.md).
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
  const int seeds = 100;
  const Spread spread = measure_seeds(eye, seeds);
  SCOPED_TRACE(testing::Message() << "ring log s " << ring_log_s << ": mean " << spread.mean << " SD " << spread.sd);
  EXPECT_LT(spread.sd / std::sqrt(seeds), 0.01);  // the mean is known well enough for 0.03 to mean something
  EXPECT_NEAR(spread.mean, ring_log_s, 0.03);
  std::printf("CIE age 25, pigmentation 0.5: ring log s %.4f, measured mean %.4f over %d (standard error %.4f), SD %.4f\n",
              ring_log_s, spread.mean, seeds, spread.sd / std::sqrt(seeds), spread.sd);
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

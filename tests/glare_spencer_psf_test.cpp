// Spencer et al. 1995's analytic PSF (glare/analytic/spencer_psf.h, glare/analytic/analytic_psf.h) against the
// paper's own numbers: unit volume of every component and mixture by Eq. 4, P_p(3 deg) = 1.462,
// the scattered fraction beyond 0.05 degrees at ages 20 and 60 (section 3.1.2), the halo's peak
// at 3 lambda / 568 degrees, and the 19.75 that the printed Eq. 7 drops.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "glare/analytic/analytic_psf.h"
#include "glare/analytic/spencer_psf.h"

namespace glarelab {
namespace {

double volume(const std::function<double(double)>& per_sr, double from = 0.0) {
  return radial_energy(per_sr, from, 90.0);
}

TEST(SpencerPsf, EveryComponentHasUnitVolumeByEq4) {
  EXPECT_NEAR(volume(spencer::f0_per_sr), 1.0, 1e-3);
  EXPECT_NEAR(volume(spencer::f1_per_sr), 1.0, 1e-3);
  EXPECT_NEAR(volume(spencer::f2_per_sr), 1.0, 1e-3);
  for (double nm : {400.0, 450.0, 500.0, 568.0, 600.0, 650.0, 700.0})
    EXPECT_NEAR(volume([nm](double t) { return spencer::f3_per_sr(t, nm); }), 1.0, 1e-3) << nm << " nm";
}

TEST(SpencerPsf, PrintedEq7WithoutHemengersExponentIsNotAPsf) {
  // The printed Eq. 7, exp(-(theta - 3)^2) without 19.75: its volume is sqrt(19.75) = 4.44 times
  // too large, which is why the halo uses Eq. 6's exponent.
  const double printed = volume([](double t) { return 436.9 * std::exp(-(t - 3.0) * (t - 3.0)); });
  EXPECT_NEAR(printed, std::sqrt(19.75), 0.02);
  // The constant 436.9 is the unit-volume height of Eq. 6's Gaussian at 3 degrees.
  const double height = 1.0 / (std::numbers::pi * std::numbers::pi / 90.0 * std::sqrt(std::numbers::pi / 19.75) *
                               std::sin(3.0 * std::numbers::pi / 180.0));
  EXPECT_NEAR(height, 436.9, 0.05);
}

TEST(SpencerPsf, EveryMixtureHasUnitVolumeInEveryChannel) {
  for (SpencerRegime regime : {SpencerRegime::photopic, SpencerRegime::mesopic, SpencerRegime::scotopic}) {
    const AnalyticPsf psf = AnalyticPsf::spencer(regime, 1.0, ObserverEye{20.0, 0.5});
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(volume([&](double t) { return psf.per_sr(t, c); }), 1.0, 1e-3) << to_string(regime) << " channel " << c;
    EXPECT_NEAR(volume([&](double t) { return psf.profile_per_sr(t); }), 1.0, 1e-3) << to_string(regime);
  }
  // The weights themselves sum to 1.
  for (const spencer::Mixture& m : {spencer::kPhotopic, spencer::kMesopic, spencer::kScotopic})
    EXPECT_NEAR(m.f0 + m.f1 + m.f2 + m.f3, 1.0, 1e-12);
}

TEST(SpencerPsf, PhotopicAtThreeDegreesIsThePapersValue) {
  // Section 3.1.1: P_p(3 deg) = 1.462 (f0 contributes nothing there).
  const double p3 = spencer::mixture_per_sr(spencer::kPhotopic, 3.0, 568.0);
  EXPECT_NEAR(p3, 1.462, 0.005 * 1.462);
  // And f3(3 deg, 568 nm) = 436.9.
  EXPECT_DOUBLE_EQ(spencer::f3_per_sr(3.0, 568.0), 436.9);
}

TEST(SpencerPsf, ScatteredFractionBeyondAFiftiethDegreeGrowsWithAgeAsSection312States) {
  for (const auto& [age, fraction] : {std::pair{20.0, 0.36}, std::pair{60.0, 0.45}}) {
    const AnalyticPsf psf = AnalyticPsf::spencer(SpencerRegime::photopic, 100.0, ObserverEye{age, 0.5});
    const double beyond = radial_energy([&](double t) { return psf.per_sr(t, 1); }, 0.05, 90.0);
    EXPECT_NEAR(beyond, fraction, 0.01) << "age " << age;
  }
}

TEST(SpencerPsf, AgeTermIsCappedWhereEq10WouldTurnNegative) {
  const spencer::Mixture young = spencer::with_age(spencer::kPhotopic, 20.0);
  EXPECT_NEAR(young.f0, 0.384 - 6.9e-9 * 160000.0, 1e-15);
  EXPECT_NEAR(young.f2, 0.138 + 6.9e-9 * 160000.0, 1e-15);
  const spencer::Mixture old = spencer::with_age(spencer::kScotopic, 100.0);  // 0.69 > f0's 0.282
  EXPECT_EQ(old.f0, 0.0);
  EXPECT_NEAR(old.f2, 0.207 + 0.282, 1e-15);
  EXPECT_NEAR(old.f0 + old.f1 + old.f2 + old.f3, 1.0, 1e-12);
}

TEST(SpencerPsf, HaloPeaksAtThreeLambdaOver568Degrees) {
  for (double nm : {400.0, 568.0, 700.0}) {
    double best_angle = 0.0, best = -1.0;
    for (double t = 1.5; t <= 4.5; t += 1e-5) {
      const double v = spencer::f3_per_sr(t, nm);
      if (v > best) best = v, best_angle = t;
    }
    EXPECT_NEAR(best_angle, 3.0 * nm / 568.0, 2e-5) << nm << " nm";
    EXPECT_NEAR(spencer::halo_peak_deg(nm), 3.0 * nm / 568.0, 1e-15);
  }
  // Per channel the colour shows: red's ring lies outside blue's.
  const AnalyticPsf psf = AnalyticPsf::spencer(spencer::kScotopic);
  auto peak_of = [&](int c) {
    double best_angle = 0.0, best = -1.0;
    for (double t = 1.5; t <= 4.5; t += 1e-3) {
      const double v = psf.per_sr(t, c) - spencer::kScotopic.f1 * spencer::f1_per_sr(t) - spencer::kScotopic.f2 * spencer::f2_per_sr(t);
      if (v > best) best = v, best_angle = t;
    }
    return best_angle;
  };
  EXPECT_GT(peak_of(0), peak_of(1));
  EXPECT_GT(peak_of(1), peak_of(2));
}

TEST(SpencerPsf, TabulatedHaloMatchesTheSpectralSum) {
  const AnalyticPsf psf = AnalyticPsf::spencer(spencer::Mixture{0.0, 0.0, 0.0, 1.0});
  const HaloSpectrum spectrum = spencer_halo_spectrum();
  for (int c = 0; c < 3; ++c) {
    double weights = 0.0;
    for (double w : spectrum.channel_weights[c]) weights += w;
    EXPECT_NEAR(weights, 1.0, 1e-12);
    for (double t = 1.0; t < 4.8; t += 0.0137) {
      double direct = 0.0;
      for (std::size_t i = 0; i < spectrum.wavelengths_nm.size(); ++i)
        direct += spectrum.channel_weights[c][i] * spencer::f3_per_sr(t, spectrum.wavelengths_nm[i]);
      EXPECT_NEAR(psf.per_sr(t, c), direct, 1e-7 * 436.9) << "channel " << c << " at " << t;
    }
  }
}

TEST(SpencerPsf, AdaptiveRegimeFollowsTheLuminanceBandsWithoutJumps) {
  auto close = [](const spencer::Mixture& a, const spencer::Mixture& b) {
    return std::abs(a.f0 - b.f0) + std::abs(a.f1 - b.f1) + std::abs(a.f2 - b.f2) + std::abs(a.f3 - b.f3) < 1e-12;
  };
  EXPECT_TRUE(close(spencer::regime_mixture(SpencerRegime::adaptive, 0.001), spencer::kScotopic));
  EXPECT_TRUE(close(spencer::regime_mixture(SpencerRegime::adaptive, 0.2), spencer::kMesopic));
  EXPECT_TRUE(close(spencer::regime_mixture(SpencerRegime::adaptive, 100.0), spencer::kPhotopic));
  // Halfway at each boundary.
  const spencer::Mixture at_001 = spencer::regime_mixture(SpencerRegime::adaptive, 0.01);
  EXPECT_NEAR(at_001.f3, 0.5 * (spencer::kScotopic.f3 + spencer::kMesopic.f3), 1e-12);
  const spencer::Mixture at_3 = spencer::regime_mixture(SpencerRegime::adaptive, 3.0);
  EXPECT_NEAR(at_3.f3, 0.5 * spencer::kMesopic.f3, 1e-12);
  // No jump: over 1/1000 decade steps the weights move by at most the smoothstep's steepest slope
  // (1.5 / 0.5 decades) times the largest weight difference, times the step.
  double previous = spencer::regime_mixture(SpencerRegime::adaptive, 1e-4).f0;
  for (double log_l = -4.0; log_l <= 3.0; log_l += 1e-3) {
    const spencer::Mixture m = spencer::regime_mixture(SpencerRegime::adaptive, std::pow(10.0, log_l));
    EXPECT_LE(std::abs(m.f0 - previous), 3.0 * 0.102 * 1e-3 + 1e-12) << log_l;
    EXPECT_NEAR(m.f0 + m.f1 + m.f2 + m.f3, 1.0, 1e-12);
    previous = m.f0;
  }
}

TEST(SpencerPsf, RegimeNamesParseAndUnknownOnesAreRefused) {
  EXPECT_EQ(parse_spencer_regime("scotopic"), SpencerRegime::scotopic);
  EXPECT_EQ(parse_spencer_regime("adaptive"), SpencerRegime::adaptive);
  EXPECT_THROW(parse_spencer_regime("twilight"), std::invalid_argument);
  EXPECT_EQ(parse_glare_model("hybrid"), GlareModel::hybrid);
  EXPECT_THROW(parse_glare_model("vos"), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab

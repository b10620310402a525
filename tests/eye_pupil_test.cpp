// Pupil and hippus (Ritschel et al. 2009 Eqs. 1 and 2) and the time-damped field luminance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "glare/eye/eye_model.h"
#include "glare/eye/pupil_model.h"

namespace glarelab {
namespace {

TEST(EyePupil, MoonSpencerMatchesHandComputedValues) {
  // p = 4.9 - 3 tanh(0.4 (log10 L + 1)), evaluated by hand (tanh(0.4) = 0.379949, tanh(0.8) = 0.664037,
  // tanh(1.2) = 0.833655, tanh(2.0) = 0.964028).
  EXPECT_NEAR(moon_spencer_pupil_diameter_mm(0.1), 4.9, 1e-12);  // log10 L + 1 = 0
  EXPECT_NEAR(moon_spencer_pupil_diameter_mm(1.0), 4.9 - 3 * 0.379949, 1e-5);
  EXPECT_NEAR(moon_spencer_pupil_diameter_mm(10.0), 4.9 - 3 * 0.664037, 1e-5);
  EXPECT_NEAR(moon_spencer_pupil_diameter_mm(100.0), 4.9 - 3 * 0.833655, 1e-5);
  EXPECT_NEAR(moon_spencer_pupil_diameter_mm(1e4), 4.9 - 3 * 0.964028, 1e-5);
  // Spencer et al. 1995 section 3.1.1: "about 3 mm for L = 10 cd/m2".
  EXPECT_NEAR(moon_spencer_pupil_diameter_mm(10.0), 3.0, 0.1);
  // Asymptotes 7.9 mm (dark) and 1.9 mm (bright).
  EXPECT_NEAR(moon_spencer_pupil_diameter_mm(1e-20), 7.9, 1e-3);
  EXPECT_NEAR(moon_spencer_pupil_diameter_mm(1e20), 1.9, 1e-3);
}

struct HippusStatistics {
  double mean_mm = 0.0;
  double sd_mm = 0.0;
  double min_mm = 1e9, max_mm = -1e9;
};

HippusStatistics hippus_over(const EyeModel& eye, double duration_s, double rate_hz) {
  HippusStatistics s;
  const int n = static_cast<int>(duration_s * rate_hz);
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < n; ++k) {
    const double d = eye.state_at(k / rate_hz).pupil_diameter_mm;
    sum += d;
    sum2 += d * d;
    s.min_mm = std::min(s.min_mm, d);
    s.max_mm = std::max(s.max_mm, d);
  }
  s.mean_mm = sum / n;
  s.sd_mm = std::sqrt(std::max(0.0, sum2 / n - s.mean_mm * s.mean_mm));
  return s;
}

TEST(EyePupil, HippusMeanOverSixtySecondsMatchesEq2) {
  for (const double luminance : {0.01, 1.0, 100.0, 1e4}) {
    EyeParameters parameters;
    parameters.initial_field_luminance_cd_m2 = luminance;
    const EyeModel eye(parameters, 7);
    const HippusStatistics s = hippus_over(eye, 60.0, 30.0);
    EXPECT_NEAR(s.mean_mm, moon_spencer_pupil_diameter_mm(luminance), 0.1) << "L = " << luminance << " cd/m2";
    EXPECT_GT(s.sd_mm, 0.0) << "the pupil must oscillate (hippus)";
    std::printf("hippus L = %g cd/m2: mean %.4f mm, Eq. 2 %.4f mm, error %+.4f mm, sd %.4f mm, range [%.3f, %.3f] mm\n",
                luminance, s.mean_mm, moon_spencer_pupil_diameter_mm(luminance),
                s.mean_mm - moon_spencer_pupil_diameter_mm(luminance), s.sd_mm, s.min_mm, s.max_mm);
  }
}

TEST(EyePupil, HippusAmplitudeGrowsWithLuminanceAsEq1Predicts) {
  // Ritschel Fig. 3: brighter conditions give stronger oscillations. Eq. 1 predicts a standard
  // deviation of noise_scale * (p_max / p) sqrt(1 - p / p_max) * sd(noise); sd(noise) of three-octave
  // value noise is known in closed form. Averaged over 6 eyes for a stable estimate.
  const std::vector<double> luminances = {0.01, 1.0, 100.0, 1e4};
  std::vector<double> measured;
  for (const double luminance : luminances) {
    EyeParameters parameters;
    parameters.initial_field_luminance_cd_m2 = luminance;
    double sd_sum = 0.0;
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
      const PupilModel pupil(parameters, seed);
      const double p = pupil.mean_diameter_mm(luminance);
      double sum = 0.0, sum2 = 0.0;
      const int n = 1800;
      for (int k = 0; k < n; ++k) {
        const double d = pupil.hippus_diameter_mm(k / 30.0, p);
        sum += d;
        sum2 += d * d;
      }
      sd_sum += std::sqrt(sum2 / n - (sum / n) * (sum / n));
    }
    const double sd = sd_sum / 6.0;
    measured.push_back(sd);
    const double p = moon_spencer_pupil_diameter_mm(luminance);
    const double predicted = 0.1 * (9.0 / p) * std::sqrt(1.0 - p / 9.0) * ValueNoise::standard_deviation();
    EXPECT_NEAR(sd / predicted, 1.0, 0.3) << "L = " << luminance << ": sd " << sd << " mm, Eq. 1 " << predicted;
    std::printf("hippus amplitude L = %g cd/m2 (p = %.3f mm): sd %.4f mm over 6 eyes, Eq. 1 predicts %.4f mm\n", luminance,
                p, sd, predicted);
  }
  for (std::size_t k = 1; k < measured.size(); ++k)
    EXPECT_GT(measured[k], measured[k - 1]) << "amplitude must grow with luminance: " << luminances[k - 1] << " -> "
                                            << luminances[k] << " cd/m2";
}

TEST(EyePupil, DiameterIsClampedToThePhysiologicalRange) {
  // A strong noise scale pushes Eq. 1 far outside [1.5, 9] mm; the clamp must hold.
  EyeParameters parameters;
  parameters.hippus_noise_amplitude = 1.0;
  const PupilModel pupil(parameters, 3);
  double low = 1e9, high = -1e9;
  for (int k = 0; k < 6000; ++k) {
    low = std::min(low, pupil.hippus_diameter_mm(k * 0.01, 1.95));
    high = std::max(high, pupil.hippus_diameter_mm(k * 0.01, 7.9));
  }
  EXPECT_GE(low, 1.5);
  EXPECT_LE(high, 9.0);
  EXPECT_EQ(low, 1.5) << "the noise at p = 1.95 mm reaches below 1.5 mm, so the clamp must have acted";
}

TEST(EyePupil, FieldLuminanceIsAFirstOrderLowPassIndependentOfFrameRate) {
  EyeParameters parameters;
  parameters.initial_field_luminance_cd_m2 = 1.0;
  FieldLuminanceHistory at60(parameters), at144(parameters);
  for (int k = 0; k <= 60; ++k) at60.record_frame(k / 60.0, 1000.0);
  for (int k = 0; k <= 144; ++k) at144.record_frame(k / 144.0, 1000.0);
  // tau(1000) = sigma tau_rod + (1 - sigma) tau_cone with sigma = 0.04 / 1000.04 (Luidolt Eq. 5.3-5.4).
  const double sigma = 0.04 / 1000.04;
  const double tau = sigma * 0.4 + (1 - sigma) * 0.1;
  EXPECT_NEAR(at60.time_constant_s(1000.0), tau, 1e-15);
  for (const double t : {0.05, 0.1, 0.3, 0.9}) {
    const double expected = 1000.0 + (1.0 - 1000.0) * std::exp(-t / tau);
    EXPECT_NEAR(at60.field_luminance_cd_m2(t), expected, 1e-9 * 1000.0) << t;
    EXPECT_NEAR(at144.field_luminance_cd_m2(t), expected, 1e-9 * 1000.0) << t;
  }
  // Dark adaptation uses the slower rod constant: at Y = 0, tau = 0.4 s.
  FieldLuminanceHistory dark(parameters);
  dark.record_frame(0.0, 0.0);
  EXPECT_NEAR(dark.field_luminance_cd_m2(0.4), std::exp(-1.0), 1e-12);
}

TEST(EyePupil, RecordedFramesDriveThePupil) {
  EyeParameters parameters;
  parameters.initial_field_luminance_cd_m2 = 0.01;
  parameters.hippus_noise_amplitude = 0.0;
  EyeModel eye(parameters, 1);
  for (int k = 0; k < 120; ++k) eye.record_frame_luminance(k / 60.0, 1e4);
  // At the first frame the field is still the dark one; 1.9 s (19 cone time constants) later it is bright.
  EXPECT_NEAR(eye.state_at(0.0).pupil_diameter_mm, moon_spencer_pupil_diameter_mm(0.01), 1e-9);
  EXPECT_NEAR(eye.state_at(1.9).pupil_diameter_mm, moon_spencer_pupil_diameter_mm(1e4), 1e-6);
  EXPECT_THROW(eye.record_frame_luminance(1.0, 5.0), std::invalid_argument);  // out of time order
  EXPECT_THROW(eye.record_frame_luminance(3.0, -1.0), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab

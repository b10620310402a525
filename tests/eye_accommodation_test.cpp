// Accommodation microfluctuations: a low-frequency component (< 0.6 Hz) whose power grows with pupil
// size and a narrow 1.3-2.1 Hz component (Ritschel et al. 2009 section 3.3, after Gray et al. 1993).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "glare/eye/eye_model.h"

namespace glarelab {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Periodogram of a Hann-windowed signal by a direct DFT at the frequencies k / T (independent of the
// model's construction: the model knows nothing of Fourier transforms).
struct Spectrum {
  std::vector<double> frequency_hz;
  std::vector<double> power;
  double band(double low_hz, double high_hz) const {
    double sum = 0.0;
    for (std::size_t k = 0; k < power.size(); ++k)
      if (frequency_hz[k] >= low_hz && frequency_hz[k] < high_hz) sum += power[k];
    return sum;
  }
};

Spectrum periodogram(const std::vector<double>& signal, double rate_hz, double max_hz) {
  const std::size_t n = signal.size();
  double mean = 0.0;
  for (double v : signal) mean += v;
  mean /= static_cast<double>(n);
  Spectrum spectrum;
  const double duration_s = static_cast<double>(n) / rate_hz;
  for (int k = 1; k / duration_s <= max_hz; ++k) {
    const double f = k / duration_s;
    std::complex<double> sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double window = 0.5 - 0.5 * std::cos(2 * kPi * static_cast<double>(i) / static_cast<double>(n - 1));
      const double phase = -2 * kPi * f * static_cast<double>(i) / rate_hz;
      sum += (signal[i] - mean) * window * std::complex<double>(std::cos(phase), std::sin(phase));
    }
    spectrum.frequency_hz.push_back(f);
    spectrum.power.push_back(std::norm(sum));
  }
  return spectrum;
}

std::vector<double> defocus_trace(double field_luminance_cd_m2, std::uint64_t seed, double duration_s, double rate_hz) {
  EyeParameters parameters;
  parameters.initial_field_luminance_cd_m2 = field_luminance_cd_m2;
  const EyeModel eye(parameters, seed);
  std::vector<double> trace;
  for (int k = 0; k < static_cast<int>(duration_s * rate_hz); ++k)
    trace.push_back(eye.accommodation().fluctuation_dioptres(k / rate_hz, eye.state_at(0).mean_pupil_diameter_mm));
  return trace;
}

TEST(EyeAccommodation, HighFrequencyPeakLiesInThe13To21HzBand) {
  const double rate_hz = 10.0, duration_s = 200.0;
  const Spectrum s = periodogram(defocus_trace(100.0, 5, duration_s, rate_hz), rate_hz, 5.0);
  std::size_t peak = 0;
  for (std::size_t k = 0; k < s.power.size(); ++k)
    if (s.frequency_hz[k] > 0.6 && (peak == 0 || s.power[k] > s.power[peak])) peak = k;
  EXPECT_GE(s.frequency_hz[peak], 1.3);
  EXPECT_LE(s.frequency_hz[peak], 2.1);
  const double in_band = s.band(1.3, 2.1);
  EXPECT_GT(in_band, 20.0 * s.band(0.7, 1.2)) << "band must be narrow: little power between the components";
  EXPECT_GT(in_band, 20.0 * s.band(2.2, 5.0));
  std::printf("accommodation band peak at %.3f Hz; in-band / (0.7-1.2 Hz) power = %.1f\n", s.frequency_hz[peak],
              in_band / s.band(0.7, 1.2));
}

TEST(EyeAccommodation, InstantaneousFrequencyStaysWithinTheBand) {
  EyeParameters parameters;
  const AccommodationModel model(parameters, 11);
  for (int k = 0; k < 20000; ++k) {
    const double f = model.high_frequency_instantaneous_hz(k * 0.013);
    ASSERT_GE(f, 1.3);
    ASSERT_LE(f, 2.1);
  }
}

TEST(EyeAccommodation, LowFrequencyPowerGrowsWithPupilSizeAndStaysBelow06Hz) {
  const double rate_hz = 10.0, duration_s = 200.0;
  // Dark field (large pupil, Eq. 2: 6.04 mm) against a bright one (2.01 mm).
  const Spectrum dark = periodogram(defocus_trace(0.01, 5, duration_s, rate_hz), rate_hz, 5.0);
  const Spectrum bright = periodogram(defocus_trace(1e4, 5, duration_s, rate_hz), rate_hz, 5.0);
  const double ratio = dark.band(0.0, 0.6) / bright.band(0.0, 0.6);
  EXPECT_GT(ratio, 2.0);
  const double p_dark = moon_spencer_pupil_diameter_mm(0.01), p_bright = moon_spencer_pupil_diameter_mm(1e4);
  // RMS proportional to the pupil diameter: power ratio (6.04 / 2.01)^2 = 9.0, within the leakage of
  // the high-frequency component into the low band.
  EXPECT_NEAR(ratio, (p_dark / p_bright) * (p_dark / p_bright), 0.15 * (p_dark / p_bright) * (p_dark / p_bright));
  // The low-frequency component alone: at least 95% of its power lies below 0.6 Hz.
  EyeParameters parameters;
  const AccommodationModel model(parameters, 5);
  std::vector<double> low;
  for (int k = 0; k < static_cast<int>(duration_s * rate_hz); ++k) low.push_back(model.low_frequency_dioptres(k / rate_hz, 6.0));
  const Spectrum l = periodogram(low, rate_hz, 5.0);
  EXPECT_GT(l.band(0.0, 0.6) / l.band(0.0, 5.0), 0.95);
  std::printf("low-frequency power ratio dark/bright pupil = %.2f (expected %.2f); fraction below 0.6 Hz = %.4f\n", ratio,
              (p_dark / p_bright) * (p_dark / p_bright), l.band(0.0, 0.6) / l.band(0.0, 5.0));
}

TEST(EyeAccommodation, DefocusIsAccommodationMinusDemand) {
  EyeParameters parameters;
  const EyeModel eye(parameters, 2);
  const EyeState s = eye.state_at(4.2);
  EXPECT_DOUBLE_EQ(s.accommodation_dioptres, parameters.accommodative_demand_dioptres + s.defocus_dioptres);
  EXPECT_EQ(eye.geometry_at(4.2).defocus_dioptres, s.defocus_dioptres);
  EXPECT_LT(std::abs(s.defocus_dioptres), 1.0);  // microfluctuations are tenths of a dioptre
}

}  // namespace
}  // namespace glarelab

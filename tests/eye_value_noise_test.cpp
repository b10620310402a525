// Three-octave value noise (Ebert et al. 2003), the noise of Ritschel Eq. 1.
#include <gtest/gtest.h>

#include <cmath>

#include "glare/eye/value_noise.h"

namespace glarelab {
namespace {

TEST(EyeValueNoise, RangeMeanAndStandardDeviationMatchTheory) {
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const ValueNoise noise(seed, EyeChannel::hippus);
    for (int k = 0; k < 40000; ++k) {
      const double v = noise(k * 0.173);
      ASSERT_GE(v, -1.0);
      ASSERT_LE(v, 1.0);
      sum += v;
      sum2 += v * v;
      ++n;
    }
  }
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.01);
  // sd = sqrt((1/3)(26/35)(1 + 1/4 + 1/16)) / 1.75 = 0.3258 (derived in glare/eye/value_noise.h).
  EXPECT_NEAR(ValueNoise::standard_deviation(), 0.32576, 1e-4);
  EXPECT_NEAR(sd / ValueNoise::standard_deviation(), 1.0, 0.03);
}

TEST(EyeValueNoise, DerivativeMatchesFiniteDifferencesAndItsBound) {
  const ValueNoise noise(9, EyeChannel::accommodation_high_phase);
  const double h = 1e-6;
  double largest = 0.0;
  for (int k = 0; k < 5000; ++k) {
    const double x = 0.0137 + k * 0.0511;
    const double numeric = (noise(x + h) - noise(x - h)) / (2 * h);
    EXPECT_NEAR(noise.derivative(x), numeric, 1e-5) << x;
    largest = std::max(largest, std::abs(numeric));
  }
  EXPECT_LE(largest, ValueNoise::kMaxDerivative);
}

TEST(EyeValueNoise, ChannelsAndSeedsAreIndependent) {
  const ValueNoise a(1, EyeChannel::hippus), b(1, EyeChannel::accommodation_low), c(2, EyeChannel::hippus);
  EXPECT_NE(a(3.3), b(3.3));
  EXPECT_NE(a(3.3), c(3.3));
  EXPECT_EQ(a(3.3), ValueNoise(1, EyeChannel::hippus)(3.3));
  // Continuity across a lattice point.
  EXPECT_NEAR(a(5.0 - 1e-9), a(5.0 + 1e-9), 1e-7);
}

}  // namespace
}  // namespace glarelab

// core/half_float.h against OpenEXR's Imath::half (a second implementation: round to nearest even,
// IEEE 754 binary16), over every half and a sweep of float bit patterns; where the two part by
// design (magnitudes that round past 65504) the clamp is checked on its own.
#include <gtest/gtest.h>

#include <Imath/half.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/half_float.h"

namespace glarelab {
namespace {

TEST(HalfFloat, EveryHalfWidensToTheSameFloatAsImath) {
  for (std::uint32_t bits = 0; bits <= 0xffffu; ++bits) {
    const auto h = static_cast<std::uint16_t>(bits);
    const float ours = float_from_half(h);
    const float imath = static_cast<float>(half(half::FromBits, h));
    if (std::isnan(imath)) {
      EXPECT_TRUE(std::isnan(ours)) << std::hex << bits;
      continue;
    }
    ASSERT_EQ(std::bit_cast<std::uint32_t>(ours), std::bit_cast<std::uint32_t>(imath)) << std::hex << bits;
  }
}

TEST(HalfFloat, NarrowsLikeImathToNearestEvenBelowTheLargestHalf) {
  // Every 61st float bit pattern from 0 up to 65520 (both signs): normals, subnormals, zero and the
  // halfway cases among them.
  int checked = 0;
  for (std::uint32_t bits = 0; bits < 0x477ff000u; bits += 61) {
    for (const std::uint32_t sign : {0u, 0x80000000u}) {
      const float value = std::bit_cast<float>(bits | sign);
      ASSERT_EQ(half_from_float(value), half(value).bits()) << value;
      ++checked;
    }
  }
  EXPECT_GT(checked, 30000000);
  // Exact halfway points, each rounding to the even neighbour: 1 + 2^-11 -> 1; 1 + 3 x 2^-11 -> 1 + 2^-9.
  EXPECT_EQ(half_from_float(1.0f + std::ldexp(1.0f, -11)), 0x3c00);
  EXPECT_EQ(half_from_float(1.0f + 3.0f * std::ldexp(1.0f, -11)), 0x3c02);
  // The smallest subnormal half is 2^-24; half of it rounds to zero (even), a little more to it.
  EXPECT_EQ(half_from_float(std::ldexp(1.0f, -25)), 0x0000);
  EXPECT_EQ(half_from_float(std::ldexp(1.5f, -25)), 0x0001);
}

TEST(HalfFloat, ClampsToTheLargestFiniteHalfWhereRoundingWouldOverflow) {
  EXPECT_EQ(half_from_float(65504.0f), 0x7bff);
  EXPECT_EQ(half_from_float(65519.99f), 0x7bff);  // Imath too: below the halfway point
  EXPECT_EQ(half(65520.0f).bits(), 0x7c00);       // Imath: infinity
  EXPECT_EQ(half_from_float(65520.0f), 0x7bff);   // here: the largest finite half
  EXPECT_EQ(half_from_float(1e30f), 0x7bff);
  EXPECT_EQ(half_from_float(-std::numeric_limits<float>::infinity()), 0xfbff);
  EXPECT_EQ(float_from_half(0x7bff), kLargestHalf);
  EXPECT_TRUE(std::isnan(float_from_half(half_from_float(std::numeric_limits<float>::quiet_NaN()))));
}

TEST(HalfFloat, RelativeErrorOfNormalsIsAtMostTwoToTheMinusEleven) {
  for (float value = 6.2e-5f; value < 65000.0f; value *= 1.0009765f) {
    const float back = float_from_half(half_from_float(value));
    EXPECT_LE(std::abs(back - value) / value, std::ldexp(1.0, -11)) << value;
  }
}

}  // namespace
}  // namespace glarelab

// The RGBA row copies of the planned convolution (glare/cpu/rgba_rows.h) against the per-value rule
// they implement: each R, G, B >= 0 and finite, alpha unchecked; the copies exact to the bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "glare/cpu/rgba_rows.h"

namespace glarelab {
namespace {

// Pixel values with distinct bit patterns: x + c / 8 + 1/1024 (exact in float).
std::vector<float> ramp(int width) {
  std::vector<float> rgba(4 * static_cast<std::size_t>(width));
  for (std::size_t k = 0; k < rgba.size(); ++k)
    rgba[k] = static_cast<float>(k / 4) + static_cast<float>(k % 4) / 8.0f + 1.0f / 1024.0f;
  return rgba;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(GlareRgbaRows, SplitCopiesEveryChannelAndJoinPutsThemBack) {
  // Widths around the four-pixel steps: the vector part, its tail, and a row of only a tail.
  for (int width : {0, 1, 3, 4, 5, 7, 8, 9, 17}) {
    const std::vector<float> rgba = ramp(width);
    std::vector<float> red(static_cast<std::size_t>(width)), green(red.size()), blue(red.size()), alpha(red.size());
    EXPECT_TRUE(split_rgba_row(rgba.data(), width, red.data(), green.data(), blue.data(), alpha.data())) << width;
    for (int x = 0; x < width; ++x) {
      const auto at = static_cast<std::size_t>(x);
      EXPECT_EQ(red[at], rgba[4 * at]);
      EXPECT_EQ(green[at], rgba[4 * at + 1]);
      EXPECT_EQ(blue[at], rgba[4 * at + 2]);
      EXPECT_EQ(alpha[at], rgba[4 * at + 3]);
    }
    std::vector<float> joined(rgba.size(), -1.0f);
    join_rgba_row(red.data(), green.data(), blue.data(), alpha.data(), width, joined.data());
    EXPECT_EQ(joined, rgba) << width;
    // Without an alpha plane the colour planes are the same.
    std::vector<float> red2(red.size());
    EXPECT_TRUE(split_rgba_row(rgba.data(), width, red2.data(), green.data(), blue.data(), nullptr));
    EXPECT_EQ(red2, red);
  }
}

TEST(GlareRgbaRows, EveryBadValueInEveryChannelAndPlaceIsCaught) {
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                       -std::numeric_limits<float>::infinity(), -1e-30f, -1.0f};
  const int width = 11;  // two vector steps and a tail of 3
  for (float value : bad)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 4; ++c) {
        std::vector<float> rgba = ramp(width);
        rgba[4 * static_cast<std::size_t>(x) + static_cast<std::size_t>(c)] = value;
        std::vector<float> red(width), green(width), blue(width), alpha(width);
        const bool clean = split_rgba_row(rgba.data(), width, red.data(), green.data(), blue.data(), alpha.data());
        // The rule: R, G, B must be >= 0 and finite; alpha is passed through unchecked.
        EXPECT_EQ(clean, c == 3) << "value " << value << " at pixel " << x << ", channel " << c;
        // The bad value is still copied as it is (the caller refuses the whole scene).
        const float* planes[4] = {red.data(), green.data(), blue.data(), alpha.data()};
        EXPECT_TRUE(same_bits(planes[c][x], value)) << "value " << value << " at pixel " << x << ", channel " << c;
      }
  // -0 and the largest float are valid, as the scalar comparisons had them.
  std::vector<float> rgba = ramp(width);
  rgba[0] = -0.0f;
  rgba[5] = std::numeric_limits<float>::max();
  rgba[4 * 10 + 2] = std::numeric_limits<float>::denorm_min();
  std::vector<float> red(width), green(width), blue(width);
  EXPECT_TRUE(split_rgba_row(rgba.data(), width, red.data(), green.data(), blue.data(), nullptr));
  EXPECT_TRUE(std::signbit(red[0]));
}

}  // namespace
}  // namespace glarelab

// core/fft_size.h against sizes factored by hand: the next length with prime factors 2, 3, 5, 7
// (good_fft_size) or 2, 3, 5 (smooth_fft_size), and a length already of that form kept as it is.
#include <gtest/gtest.h>

#include "core/fft_size.h"

namespace glarelab {
namespace {

TEST(FftSize, NextLengthWithSmallPrimeFactors) {
  EXPECT_EQ(good_fft_size(0), 1);  // no length below 1
  EXPECT_EQ(good_fft_size(1), 1);
  EXPECT_EQ(good_fft_size(11), 12);      // 2^2 3
  EXPECT_EQ(good_fft_size(13), 14);      // 2 7
  EXPECT_EQ(good_fft_size(97), 98);      // 2 7^2
  EXPECT_EQ(good_fft_size(121), 125);    // 122 = 2 61, 123 = 3 41, 124 = 2^2 31; 5^3
  EXPECT_EQ(good_fft_size(1021), 1024);  // 2^10
  EXPECT_EQ(good_fft_size(1025), 1029);  // 3 7^3
  EXPECT_EQ(good_fft_size(1029), 1029);
}

TEST(FftSize, SmoothLengthsLeaveOutSeven) {
  EXPECT_EQ(smooth_fft_size(0), 1);
  EXPECT_EQ(smooth_fft_size(13), 15);      // 14 = 2 7 is not 5-smooth; 3 5
  EXPECT_EQ(smooth_fft_size(97), 100);     // 98 = 2 7^2, 99 = 3^2 11; 2^2 5^2
  EXPECT_EQ(smooth_fft_size(1021), 1024);
  EXPECT_EQ(smooth_fft_size(1025), 1080);  // past 3 7^3 = 1029 to 2^3 3^3 5
  EXPECT_EQ(smooth_fft_size(1080), 1080);
}

}  // namespace
}  // namespace glarelab

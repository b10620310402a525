// Each pixel's solid angle relative to the line of sight's (glare/analytic/pixel_solid_angle.h)
// against the solid angle integrated over the pixel's area here (a 64 x 64 midpoint rule of
// d / r^3 dA), and the luminance-energy round trip.
#include <gtest/gtest.h>

#include <cmath>

#include "glare/analytic/pixel_solid_angle.h"

namespace glarelab {
namespace {

// The solid angle of the pixel whose corner lies at (x0, y0) mm from the line of sight's foot.
double integrated_solid_angle_sr(double x0_mm, double y0_mm, double pitch_mm, double distance_mm) {
  constexpr int kSteps = 64;
  const double h = pitch_mm / kSteps;
  double sum = 0.0;
  for (int i = 0; i < kSteps; ++i)
    for (int j = 0; j < kSteps; ++j) {
      const double x = x0_mm + (i + 0.5) * h, y = y0_mm + (j + 0.5) * h;
      sum += distance_mm / std::pow(distance_mm * distance_mm + x * x + y * y, 1.5) * h * h;
    }
  return sum;
}

TEST(PixelSolidAngle, IsEachPixelsSolidAngleOverTheAxialPixels) {
  // 0.5 mm pixels at 300 mm, 1200 x 300 px: out to 45 degrees horizontally.
  const DisplayGeometry geometry{300.0, 0.5};
  constexpr int kWidth = 1200, kHeight = 300;
  const PixelSolidAngle weights(geometry, kWidth, kHeight);
  const double axial_sr = integrated_solid_angle_sr(-0.25, -0.25, 0.5, 300.0);
  for (const auto& [x, y] : {std::pair{600, 150}, std::pair{599, 149}, std::pair{800, 150}, std::pair{1199, 0},
                             std::pair{0, 299}, std::pair{1000, 20}}) {
    const double x0 = (x - 0.5 * kWidth) * 0.5, y0 = (y - 0.5 * kHeight) * 0.5;
    const double expected = integrated_solid_angle_sr(x0, y0, 0.5, 300.0) / axial_sr;
    // The pixel's centre stands for its area: within (pitch / r)^2 of the integral.
    EXPECT_NEAR(weights.relative(x, y), expected, 2e-5 * expected) << x << "," << y;
  }
  // 45 degrees off axis a pixel subtends cos^3(45 deg) = 0.354 of the axial one.
  EXPECT_NEAR(weights.relative(1199, 150), std::pow(std::cos(std::atan(299.75 / 300.0)), 3.0), 1e-5);
}

TEST(PixelSolidAngle, LuminanceToEnergyAndBackIsTheFrame) {
  const DisplayGeometry geometry{400.0, 0.3};
  const PixelSolidAngle weights(geometry, 40, 30);
  ImageRGBA frame(40, 30, 0.0f);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x)
      for (int c = 0; c < 4; ++c) frame.pixel(x, y)[c] = static_cast<float>(1 + x + 7 * y + c);
  ImageRGBA energy = weights.to_energy(frame);
  EXPECT_FLOAT_EQ(energy.pixel(39, 29)[1], frame.pixel(39, 29)[1] * weights.relative(39, 29));
  EXPECT_EQ(energy.pixel(39, 29)[3], frame.pixel(39, 29)[3]);  // alpha kept
  weights.to_luminance(energy);
  for (std::size_t i = 0; i < frame.rgba.size(); ++i) EXPECT_NEAR(energy.rgba[i], frame.rgba[i], 1e-6 * frame.rgba[i]);
  ImageRGBA wrong(41, 30, 0.0f);
  EXPECT_THROW(weights.to_luminance(wrong), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab

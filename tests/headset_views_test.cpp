// A headset view's pixel pitch (runner/session/headset_views.h) against the figures the Luidolt
// headset example states (examples/luidolt_ratings_headset.toml: halves of 640 x 690 px at
// 1.7184 mm from 600 mm span Monado's simulated views, 85 deg across and 89.2 deg high) and an
// asymmetric view checked through the angles its pixels reach.
#include <gtest/gtest.h>

#include <cmath>

#include "runner/session/headset_views.h"

namespace glarelab {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(HeadsetViews, ASymmetricViewsPitchIsTheExamplesPublishedPitch) {
  // Monado's simulated view: 85 deg across; its height from its display's 65 x 70 mm per eye,
  // 2 atan(tan(42.5 deg) x 70 / 65) = 89.22 deg.
  const double up_deg = std::atan(std::tan(42.5 * kPi / 180.0) * 70.0 / 65.0) * 180.0 / kPi;
  const ViewFieldOfView view{-42.5, 42.5, up_deg, -up_deg};
  const ViewPixelPitch pitch = view_pixel_pitch(view, 640, 690, 600.0);
  EXPECT_NEAR(pitch.across_mm, 1.7184, 5e-4);  // 1.71812: the example rounds it
  // 690 px high: the example's pixels are square to 0.2 %.
  EXPECT_NEAR(pitch.high_mm / pitch.across_mm, 1.0, 2.5e-3);
  // Twice the pixels each way, half the pitch; twice the distance, twice the pitch.
  EXPECT_NEAR(view_pixel_pitch(view, 1280, 1380, 600.0).across_mm, pitch.across_mm / 2.0, 1e-12);
  EXPECT_NEAR(view_pixel_pitch(view, 640, 690, 1200.0).high_mm, pitch.high_mm * 2.0, 1e-12);
}

TEST(HeadsetViews, AnAsymmetricViewsPixelsReachItsEdgesAngles) {
  // A view turned outwards (a canted display): 50 deg to the left of its axis, 35 to the right.
  const ViewFieldOfView view{-50.0, 35.0, 40.0, -45.0};
  const int width_px = 800, height_px = 900;
  const double distance_mm = 100.0;
  const ViewPixelPitch pitch = view_pixel_pitch(view, width_px, height_px, distance_mm);
  // The axis falls on the pixel column where the left edge's span ends: from there, the image's
  // right edge lies at the angle atan(pixels to it x pitch / d), which must be the view's right edge.
  const double axis_px = distance_mm * std::tan(50.0 * kPi / 180.0) / pitch.across_mm;
  EXPECT_NEAR(std::atan((width_px - axis_px) * pitch.across_mm / distance_mm) * 180.0 / kPi, 35.0, 1e-9);
  const double axis_row_px = distance_mm * std::tan(40.0 * kPi / 180.0) / pitch.high_mm;
  EXPECT_NEAR(std::atan((height_px - axis_row_px) * pitch.high_mm / distance_mm) * 180.0 / kPi, 45.0, 1e-9);
}

}  // namespace
}  // namespace glarelab

// The frame a condition's spectacles show the eye in a session (runner/session/condition_refraction.h,
// frame_through_spectacles): the display, a flat scene at its viewing distance, seen through the
// traced lens. Checked against the spectacle magnification of a near object, in closed form:
//
// A thin lens of power F sits h in front of the eye's centre of rotation and L in front of the
// display. The eye turns to the visual direction tan a = y / h, the height y where its line of sight
// crosses the lens; on the object side that ray has slope -y / h + y F (paraxial refraction), so it
// left the display at height y (1 + L / h - F L); seen from the centre of rotation that point lies
// at tan b = y (1 + L / h - F L) / (L + h). The angular magnification is
//   tan a / tan b = 1 / (1 - F L h / (L + h)),
// which tends to the power factor 1 / (1 - h F) of a distant object. The lens' thickness adds the
// shape factor 1 / (1 - (t / n) F1) (F1 the front surface). Without spectacles the frame is returned
// as it is.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "core/display_spec.h"
#include "core/image.h"
#include "glare/refraction/spectacle_lens.h"
#include "runner/session/condition_refraction.h"

namespace glarelab {
namespace {

// Horizontal centroid of the light in columns [x0, x1).
double centroid_x(const ImageRGBA& image, int x0, int x1) {
  double sum = 0.0, weighted = 0.0;
  for (int y = 0; y < image.height_px; ++y)
    for (int x = x0; x < x1; ++x) {
      const double g = image.pixel(x, y)[1];
      sum += g;
      weighted += g * x;
    }
  return weighted / sum;
}

TEST(RefractionSessionWarp, SpectaclesMagnifyTheDisplayAsANearObjectThroughTheLens) {
  DisplaySpec display;
  display.width_px = 641;
  display.height_px = 101;
  display.pixel_pitch_mm = 0.25;
  display.viewing_distance_mm = 400.0;
  // Two 3 x 3 bright blocks symmetric about the centre column (320), 200 px either side.
  ImageRGBA frame(display.width_px, display.height_px, 0.0f);
  for (int x0 : {117, 517})
    for (int y = 49; y <= 51; ++y)
      for (int x = x0; x < x0 + 3; ++x)
        for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = 100.0f;

  for (double power : {+4.0, -3.0}) {
    SpectacleLensSpec spec;
    spec.prescription.sphere_dioptres = power;
    ConditionRefraction refraction;
    refraction.spectacles = "test";
    refraction.traced_lens = std::make_shared<const SpectacleLens>(spec);
    const SpectacleLens& lens = *refraction.traced_lens;
    const ImageRGBA seen = frame_through_spectacles(refraction, display, frame, 2);

    const double h_m = 1e-3 * (spec.vertex_distance_mm + spec.centre_of_rotation_mm);
    const double l_m = 1e-3 * (display.viewing_distance_mm - spec.vertex_distance_mm);
    const double power_factor = 1.0 / (1.0 - power * l_m * h_m / (l_m + h_m));
    const double shape_factor =
        1.0 / (1.0 - lens.centre_thickness_m() / spec.refractive_index_d * lens.front_power_dioptres());
    const double expected = power_factor * shape_factor;
    // The distance between the two blocks' images over that between the blocks (400 px): whatever
    // half-pixel convention puts the centre, the pair is symmetric about it.
    const double measured = (centroid_x(seen, 320, 641) - centroid_x(seen, 0, 320)) / 400.0;
    std::printf("F %+.1f D: near-object spectacle magnification %.5f (power %.5f, shape %.5f), measured %.5f\n", power,
                expected, power_factor, shape_factor, measured);
    EXPECT_NEAR(measured, expected, 2e-3 * expected) << power;
    // The distant-object formula differs by more than the tolerance: the scene distance is used.
    EXPECT_GT(std::abs(1.0 / (1.0 - h_m * power) * shape_factor - expected), 4e-3 * expected) << power;
  }
}

TEST(RefractionSessionWarp, WithoutSpectaclesTheFrameIsUnchanged) {
  DisplaySpec display;
  display.width_px = 32;
  display.height_px = 16;
  ImageRGBA frame(display.width_px, display.height_px, 3.0f);
  frame.pixel(5, 7)[0] = 42.0f;
  const ConditionRefraction naked;
  const ImageRGBA seen = frame_through_spectacles(naked, display, frame, 2);
  EXPECT_EQ(seen.rgba, frame.rgba);
}

}  // namespace
}  // namespace glarelab

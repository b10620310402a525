// Depth of field with an error that depends on the line of sight (stimuli/directional_depth_of_field.h):
// the regions follow the rule worked by hand below, each region's pixels are those of a whole-frame
// pass with the region centre's error, and an error that does not depend on the direction gives the
// depth-of-field stage itself, bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "stimuli/depth_of_field.h"
#include "stimuli/directional_depth_of_field.h"

namespace glarelab {
namespace {

constexpr double kPupilRadiusM = 0.002;
// 1 mrad a pixel: with a 2 mm pupil radius a dioptre of error moves a ray by 2 px.
const double kDegreesPerPixel = 1e-3 * 180.0 / std::numbers::pi;

ImageRGBA textured(int width, int height) {
  ImageRGBA image(width, height, 1.0f);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float* p = image.pixel(x, y);
      const double checker = ((x / 4 + y / 3) % 2 == 0) ? 40.0 : 5.0;
      p[0] = static_cast<float>(checker + 8.0 * std::sin(0.7 * x) + 10.0);
      p[1] = static_cast<float>(0.5 * checker + 3.0 * std::cos(0.31 * y) + 4.0);
      p[2] = static_cast<float>(((x * 7 + y * 13) % 11) * 2.0);
    }
  return image;
}

// An emmetrope accommodated at 0.5 m whose error grows by `dioptres_per_row` per row below the
// centre row (a lens whose power changes down the frame, like a progressive's corridor).
EyeErrorAlongSightLine graded(double dioptres_per_row, double centre_row) {
  return [=](double, double y_px) {
    const double extra = dioptres_per_row * (y_px - centre_row);
    return EyeErrorAtDistance([extra](double distance_m) { return DioptricPower::spherical(2.0 - 1.0 / distance_m + extra); });
  };
}

DirectionalDepthOfFieldSettings settings_for(const EyeErrorAlongSightLine& error) {
  DirectionalDepthOfFieldSettings settings;
  settings.degrees_per_pixel = kDegreesPerPixel;
  settings.pupil_radius_m = kPupilRadiusM;
  settings.residual_error = error;
  settings.threads = 2;
  return settings;
}

// 0.01 D a row, 2 px a dioptre: a region h rows high is off at its edge rows by
// 0.01 x (h - 1) / 2 x 2 px: 64 rows 0.63 px, 32 rows 0.31 px (> 0.25: split), 16 rows 0.15 px.
// So 4 regions down, 1 across (nothing changes along x), and the corners are off by 0.15 px.
TEST(DirectionalDepthOfFieldTest, RegionsFollowTheRuleWorkedByHand) {
  const ImageRGBA image = textured(48, 64);
  const std::vector<float> depth(48 * 64, 1.0f);
  DirectionalDepthOfFieldReport report;
  apply_directional_depth_of_field(image, depth, settings_for(graded(0.01, 31.5)), &report);
  EXPECT_EQ(report.regions_x, 1);
  EXPECT_EQ(report.regions_y, 4);
  EXPECT_NEAR(report.max_direction_error_px, 0.01 * 7.5 * 2.0, 1e-9);
  EXPECT_EQ(report.layers, 4);  // a flat scene: one layer a region
  // Margin: the largest blur, 1 D + 0.01 x 24 D at the last region's centre, x 2 px, rounded up, + 2.
  EXPECT_EQ(report.margin_px, static_cast<int>(std::ceil(2.0 * (1.0 + 0.24))) + 2);
}

// Each region is what a whole-frame pass with the region centre's error gives there (the margin
// carries every neighbour's light into the region).
TEST(DirectionalDepthOfFieldTest, EachRegionIsTheWholeFramePassWithItsCentresError) {
  const ImageRGBA image = textured(48, 64);
  const std::vector<float> depth(48 * 64, 1.0f);
  const EyeErrorAlongSightLine error = graded(0.01, 31.5);
  const ImageRGBA blurred = apply_directional_depth_of_field(image, depth, settings_for(error));
  for (int region = 0; region < 4; ++region) {
    DepthOfFieldSettings whole;
    whole.degrees_per_pixel = kDegreesPerPixel;
    whole.pupil_radius_m = kPupilRadiusM;
    whole.residual_error = error(23.5, 16.0 * region + 7.5);
    const ImageRGBA expected = apply_depth_of_field(image, depth, whole);
    double largest = 0.0;
    for (int y = 16 * region; y < 16 * region + 16; ++y)
      for (int x = 0; x < 48; ++x)
        for (int c = 0; c < 3; ++c)
          largest = std::max(largest, static_cast<double>(std::abs(blurred.pixel(x, y)[c] - expected.pixel(x, y)[c])));
    // Float rounding of the direct sum against the FFT the cost model may pick for the other size.
    EXPECT_LT(largest, 1e-3) << "region " << region;
  }
  // And the regions do differ: the blur grows down the frame.
  EXPECT_NE(blurred.pixel(20, 5)[2], blurred.pixel(20, 5 + 48)[2]);
}

// An error that does not depend on the line of sight is one region: the stage itself, bit for bit,
// on a scene with two planes.
TEST(DirectionalDepthOfFieldTest, ErrorWithoutDirectionIsTheStageItself) {
  const ImageRGBA image = textured(40, 30);
  std::vector<float> depth(40 * 30, 2.0f);
  for (int y = 8; y < 22; ++y)
    for (int x = 10; x < 30; ++x) depth[static_cast<std::size_t>(y) * 40 + x] = 0.4f;
  const EyeErrorAlongSightLine error = graded(0.0, 0.0);
  DirectionalDepthOfFieldReport report;
  const ImageRGBA blurred = apply_directional_depth_of_field(image, depth, settings_for(error), &report);
  DepthOfFieldSettings whole;
  whole.degrees_per_pixel = kDegreesPerPixel;
  whole.pupil_radius_m = kPupilRadiusM;
  whole.residual_error = error(0.0, 0.0);
  whole.threads = 2;
  DepthOfFieldReport stage;
  EXPECT_EQ(blurred.rgba, apply_depth_of_field(image, depth, whole, &stage).rgba);
  EXPECT_EQ(report.regions_x * report.regions_y, 1);
  EXPECT_EQ(report.layers, stage.layers);
  EXPECT_EQ(report.max_direction_error_px, 0.0);
}

TEST(DirectionalDepthOfFieldTest, BadSettingsAreRefused) {
  const ImageRGBA image = textured(8, 8);
  const std::vector<float> depth(64, 1.0f);
  DirectionalDepthOfFieldSettings settings = settings_for(graded(0.0, 0.0));
  settings.max_regions_per_axis = 0;
  EXPECT_THROW(apply_directional_depth_of_field(image, depth, settings), std::invalid_argument);
  settings = settings_for(graded(0.0, 0.0));
  settings.pupil_radius_m = 0.0;
  EXPECT_THROW(apply_directional_depth_of_field(image, depth, settings), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab

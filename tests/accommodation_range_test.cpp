// [observer] accommodation (runner/session/condition_depth_of_field.h): "range" accommodates each
// scene point on its own (Kakimoto et al. 2007, Table 1: Eq. 13 per voxel), so points within the
// accommodation range stay sharp and points beyond it blur by their defocus from the nearer end, the
// blur circle of Eq. 8; "fixation" (the default) is the frame of one accommodation, on the view's
// centre, as before. Also the key: read, written back, refused at file:line:column.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "cli_process.h"
#include "glare/eye/pupil_model.h"
#include "glare/refraction/eye_refraction.h"
#include "protocols/experiment.h"
#include "runner/session/condition_depth_of_field.h"
#include "stimuli/display_model.h"

namespace glarelab {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// A -1.00 D myope (at 12 mm) with 2 D of accommodation left: far point about 1 m, near point about
// 0.33 m.
constexpr double kSphereDioptres = -1.0, kVertex_m = 0.012, kAmplitudeDioptres = 2.0;

ConditionRefraction myope(AccommodationRule rule) {
  ConditionRefraction refraction;
  refraction.eye.correcting_prescription.sphere_dioptres = kSphereDioptres;
  refraction.eye.prescription_vertex_distance_m = kVertex_m;
  refraction.eye.accommodation_amplitude_dioptres = kAmplitudeDioptres;
  refraction.accommodation_amplitude_dioptres = kAmplitudeDioptres;
  refraction.accommodation = rule;
  return refraction;
}

// K: the prescription moved to the cornea, Rx / (1 - d Rx).
double ocular_refraction_dioptres() { return kSphereDioptres / (1.0 - kVertex_m * kSphereDioptres); }

// Kakimoto Eq. 13 per point: the error left at vergence V = -1 / d is 0 inside [K - A, K], and
// beyond it the vergence's distance from the nearer end.
double range_error_dioptres(double distance_m) {
  const double v = std::isinf(distance_m) ? 0.0 : -1.0 / distance_m, k = ocular_refraction_dioptres();
  if (v > k) return v - k;                                  // beyond the far point
  if (v < k - kAmplitudeDioptres) return v - (k - kAmplitudeDioptres);  // nearer than the near point
  return 0.0;
}

DisplaySpec display() {
  DisplaySpec spec;
  spec.width_px = 200;
  spec.height_px = 100;
  spec.pixel_pitch_mm = 0.25;
  spec.viewing_distance_mm = 400.0;
  return spec;
}

struct Point {
  int x;
  double depth_m;
};
// Points of 1000 cd/m2 on row 50 at several depths, before a black background at infinity (farther
// than every point, so none is hidden behind it). The centre pixel (100, 50) is background.
const std::vector<Point> kPoints = {{30, 0.5}, {60, 0.8}, {130, 0.25}, {170, 3.0}};
constexpr int kRow = 50;
constexpr float kPoint_cd_m2 = 1000.0f;

ImageRGBA scene() {
  ImageRGBA image(200, 100, 0.0f);
  for (const Point& p : kPoints)
    for (int c = 0; c < 3; ++c) image.pixel(p.x, kRow)[c] = kPoint_cd_m2;
  return image;
}

std::vector<float> depths() {
  std::vector<float> depth(200 * 100, std::numeric_limits<float>::infinity());
  for (const Point& p : kPoints) depth[static_cast<std::size_t>(kRow) * 200 + p.x] = static_cast<float>(p.depth_m);
  return depth;
}

// Field luminance 0.01 cd/m2: Eq. 2 gives a 6.04 mm pupil, blur circles of several pixels.
constexpr double kField_cd_m2 = 0.01;

struct Spot {
  double sum = 0.0;
  double radius_px = 0.0;  // of the uniform disc with the spot's second moment: sqrt(2 <r^2>)
};
Spot spot_around(const ImageRGBA& image, int cx, int cy, int half) {
  Spot spot;
  double moment = 0.0;
  for (int y = cy - half; y <= cy + half; ++y)
    for (int x = cx - half; x <= cx + half; ++x) {
      const double value = image.pixel(x, y)[1];
      spot.sum += value;
      moment += value * ((x - cx) * (x - cx) + (y - cy) * (y - cy));
    }
  spot.radius_px = std::sqrt(2.0 * moment / spot.sum);
  return spot;
}

TEST(AccommodationRange, EachDepthTakesItsOwnEquation13) {
  const FrameEye eye = frame_eye(myope(AccommodationRule::range), display(), kInfinity);
  EXPECT_NEAR(eye.range_far_vergence_dioptres, ocular_refraction_dioptres(), 1e-12);
  EXPECT_NEAR(eye.range_near_vergence_dioptres, ocular_refraction_dioptres() - kAmplitudeDioptres, 1e-12);
  const EyeErrorAtDistance error = eye.error(100.0, 50.0);
  for (const double d : {0.1, 0.2, 0.25, 0.3, 0.3347, 0.34, 0.5, 0.8, 1.0, 1.02, 1.5, 3.0, 10.0, kInfinity}) {
    const DioptricPower e = error(d);
    EXPECT_NEAR(e.xx(), range_error_dioptres(d), 1e-12) << d;
    EXPECT_NEAR(e.yy(), range_error_dioptres(d), 1e-12) << d;
    EXPECT_EQ(e.xy(), 0.0) << d;
  }
}

TEST(AccommodationRange, PointsInsideTheRangeAreSharpOutsideBlurredFromTheNearerEnd) {
  const FrameDepthOfField frame =
      depth_of_field_frame(myope(AccommodationRule::range), display(), scene(), depths(), kField_cd_m2, 1);
  const double pupil_radius_m = 0.5e-3 * moon_spencer_pupil_diameter_mm(kField_cd_m2);
  const double radians_per_px = DisplayModel(display()).degrees_per_pixel_at_centre() * 3.14159265358979323846 / 180.0;
  std::printf("%s\n", describe_frame_depth_of_field(frame).c_str());
  for (const Point& p : kPoints) {
    const double error = range_error_dioptres(p.depth_m);
    const double expected_px = std::abs(error) * pupil_radius_m / radians_per_px;  // Eq. 8's a = b, in pixels
    if (error == 0.0) {
      // Within the range: the point keeps its peak, and nothing spreads around it.
      EXPECT_EQ(frame.image_cd_m2.pixel(p.x, kRow)[1], kPoint_cd_m2) << p.depth_m;
      EXPECT_EQ(frame.image_cd_m2.pixel(p.x + 1, kRow)[1], 0.0f) << p.depth_m;
      EXPECT_EQ(frame.image_cd_m2.pixel(p.x, kRow + 1)[1], 0.0f) << p.depth_m;
      continue;
    }
    // A pixelised uniform disc of radius R has <r^2> = R^2 / 2 + 1/6 (a pixel's own spread).
    const Spot spot = spot_around(frame.image_cd_m2, p.x, kRow, 12);
    const double measured_px = std::sqrt(spot.radius_px * spot.radius_px - 1.0 / 3.0);
    std::printf("point at %.2f m: error %.4f D, blur circle %.3f px (closed form %.3f px), light %.1f of %.0f\n",
                p.depth_m, error, measured_px, expected_px, spot.sum, kPoint_cd_m2);
    EXPECT_GT(expected_px, 2.5);
    EXPECT_NEAR(measured_px, expected_px, 0.05 * expected_px) << p.depth_m;
    EXPECT_NEAR(spot.sum, kPoint_cd_m2, 0.05 * kPoint_cd_m2) << p.depth_m;
    EXPECT_LT(frame.image_cd_m2.pixel(p.x, kRow)[1], 0.1f * kPoint_cd_m2) << p.depth_m;
  }
}

// The default, one accommodation on the view's centre, is the stage with the fixed accommodation of
// glare/refraction/eye_refraction.h's residual_error_at, bit for bit; the in-range points blur.
TEST(AccommodationRange, FixationIsTheFrameOfOneAccommodationAsBefore) {
  const ConditionRefraction refraction = myope(AccommodationRule::fixation);
  const FrameDepthOfField frame = depth_of_field_frame(refraction, display(), scene(), depths(), kField_cd_m2, 1);
  const RefractiveEye eye(refraction.eye);
  ViewingCondition viewing;
  viewing.fixation_distance_m = kInfinity;  // the centre pixel's depth
  DirectionalDepthOfFieldSettings settings;
  settings.degrees_per_pixel = DisplayModel(display()).degrees_per_pixel_at_centre();
  settings.pupil_radius_m = 0.5e-3 * moon_spencer_pupil_diameter_mm(kField_cd_m2);
  settings.residual_error = [eye, viewing](double, double) {
    return EyeErrorAtDistance([eye, viewing](double d) { return residual_error_at(eye, viewing, d); });
  };
  const ImageRGBA reference = apply_directional_depth_of_field(scene(), depths(), settings);
  EXPECT_TRUE(frame.image_cd_m2.rgba == reference.rgba);
  // Relaxed on infinity (the myope's accommodation stays 0), the point at 0.5 m is 1.01 D out.
  EXPECT_LT(frame.image_cd_m2.pixel(30, kRow)[1], 0.1f * kPoint_cd_m2);
  EXPECT_EQ(frame.eye.rule, AccommodationRule::fixation);
}

// --- the key ------------------------------------------------------------------------------

std::string experiment_with_observer(const std::string& observer_lines) {
  return "[observer]\n" + observer_lines +
         "\n[experiment]\nname = \"p\"\n[scenes]\na = { file = \"a.exr\" }\n[procedure]\ntype = \"forced_choice\"\n"
         "[[conditions.rows]]\nname = \"one\"\nscene_a = \"a\"\nscene_b = \"a\"\n";
}

std::string refusal(const std::string& observer_lines) {
  try {
    parse_experiment_text(experiment_with_observer(observer_lines), "p.toml", "/tmp");
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "no error";
}

TEST(AccommodationRange, TheKeyIsReadIntoEachConditionAndWrittenBack) {
  const Experiment fixation = parse_experiment_text(experiment_with_observer(""), "p.toml", "/tmp");
  EXPECT_EQ(fixation.observer_optics.accommodation, AccommodationRule::fixation);
  const Experiment range =
      parse_experiment_text(experiment_with_observer("accommodation = \"range\"\ndepth_of_field = true"), "p.toml", "/tmp");
  EXPECT_EQ(range.observer_optics.accommodation, AccommodationRule::range);
  const std::optional<ConditionRefraction> refraction = condition_refraction(range, range.conditions[0]);
  ASSERT_TRUE(refraction);
  EXPECT_EQ(refraction->accommodation, AccommodationRule::range);
  const std::string resolved = resolved_config_toml(range);
  EXPECT_NE(resolved.find("accommodation = 'range'"), std::string::npos) << resolved;
  EXPECT_EQ(parse_experiment_text(resolved, "r.toml", "/tmp").observer_optics.accommodation, AccommodationRule::range);
  EXPECT_NE(resolved_config_toml(fixation).find("accommodation = 'fixation'"), std::string::npos);
}

TEST(AccommodationRange, RefusalsNameTheKeyAndItsPlace) {
  EXPECT_EQ(refusal("accommodation = \"focus\""),
            "p.toml:2:17: key 'observer.accommodation': unknown value 'focus' (supported: 'fixation', 'range')");
  EXPECT_EQ(refusal("accommodation = 1"), "p.toml:2:17: key 'observer.accommodation': expected a string, found an integer");
  EXPECT_EQ(refusal("depth_of_field = false\naccommodation = \"range\""),
            "p.toml:3:17: key 'observer.accommodation': \"range\" accommodates each depth of the scene, but "
            "depth_of_field = false turns the depth of field off: remove one of the two");
}

TEST(AccommodationRange, BadValuesStopTheRunBeforeAnythingIsWritten) {
  const test::ScratchDir scratch;
  const auto& dir = scratch.path();
  const auto conditions = std::filesystem::path(GLARELAB_SOURCE_DIR) / "examples/demo_conditions.csv";
  const std::string demo =
      test::read_bytes(test::demo_variant(dir, {{"file", "file = \"" + conditions.string() + "\""}}));
  const int line = static_cast<int>(std::count(demo.begin(), demo.end(), '\n')) + 3;
  const auto experiment = dir / "bad.toml";
  test::write_bytes(experiment.string(), demo + "\n[observer]\naccommodation = \"ranged\"\n");
  const auto db = dir / "bad.db";
  const auto run = test::run_glarelab(
      {"run", experiment.string(), "--display", "offscreen", "--observer", "simulated", "--db", db.string()}, dir);
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find(experiment.string() + ":" + std::to_string(line) +
                            ":17: key 'observer.accommodation': unknown value 'ranged'"),
            std::string::npos)
      << run.output;
  EXPECT_FALSE(std::filesystem::exists(db));
}

}  // namespace
}  // namespace glarelab

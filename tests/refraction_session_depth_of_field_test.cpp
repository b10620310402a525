// Depth of field in a session (runner/session/condition_depth_of_field.h): the eye's error along each
// line of sight against the closed form of a thin lens at its vertex distance (Eq. 1) with the
// traced power of the lens there, a scene with two planes rendered through `glarelab render` against
// the depth-of-field stage and the geometric blur radius, and the refusals of bad depths.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <string>

#include "cli_process.h"
#include "core/exr_io.h"
#include "glare/eye/pupil_model.h"
#include "glare/refraction/spectacle_lens.h"
#include "runner/session/condition_depth_of_field.h"
#include "stimuli/depth_of_field.h"
#include "stimuli/scene_library.h"
#include "stimuli/spectacle_warp.h"

namespace glarelab {
namespace {

using test::run_glarelab;
using test::ScratchDir;

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// A display 0.4 m away whose frame reaches 30 deg below the centre: only its geometry is used.
DisplaySpec tall_display() {
  DisplaySpec display;
  display.width_px = 400;
  display.height_px = 2000;
  display.pixel_pitch_mm = 0.25;
  display.viewing_distance_mm = 400.0;
  return display;
}

// A presbyope with no accommodation left (amplitude 0) and no distance error, wearing `lens`.
ConditionRefraction wearing(const SpectacleLensSpec& lens) {
  ConditionRefraction refraction;
  refraction.eye.accommodation_amplitude_dioptres = 0.0;
  refraction.spectacles = "test";
  refraction.traced_lens = std::make_shared<const SpectacleLens>(lens);
  return refraction;
}

// The pencil from a point d in front of the cornea: vergence -1 / (d - h) at the lens, plus the
// lens' power F there, carried the vertex distance h to the cornea: V / (1 - h V) (Eq. 1).
double at_cornea(double distance_m, double lens_power_dioptres, double vertex_m) {
  const double at_lens = (std::isinf(distance_m) ? 0.0 : -1.0 / (distance_m - vertex_m)) + lens_power_dioptres;
  return at_lens / (1.0 - vertex_m * at_lens);
}

// Straight ahead and through the near reference point of a progressive lens (plano, +2.00 add): the
// design puts the distance power on the fitting cross and distance + add on the line of sight
// through the point corridor_length_mm below it (docs/SPECTACLES.md). The eye, accommodated on the
// centre (amplitude 0: not at all), sees a point 0.4 m away with -2.50 D straight ahead and with
// the add's help through the near zone.
TEST(RefractionSessionDepthOfField, ProgressiveNearZoneSetsTheBlurBelowTheCentre) {
  SpectacleLensSpec spec;
  spec.near_add_dioptres = 2.0;
  const ConditionRefraction refraction = wearing(spec);
  const DisplaySpec display = tall_display();
  const FrameEye eye = frame_eye(refraction, display, 0.4);
  const double vertex_m = 1e-3 * spec.vertex_distance_mm;
  EXPECT_NEAR(eye.accommodation_dioptres, 0.0, 1e-12);
  const SpectacleFrame frame{display.width_px, display.height_px, display.pixel_pitch_mm / display.viewing_distance_mm * kDegPerRad};

  // Straight ahead: -1 / 0.4 m exactly (the point's own vergence, as without a lens, for a plano).
  const DioptricPower ahead = eye.error(display.width_px / 2, display.height_px / 2)(0.4);
  EXPECT_NEAR(ahead.mean_dioptres(), at_cornea(0.4, 0.0, vertex_m), 2e-3);
  EXPECT_NEAR(ahead.mean_dioptres(), -2.5, 2e-3);

  // The line of sight through the near reference point, found as the lens finds it.
  const SpectacleLens& lens = *refraction.traced_lens;
  const glm::dvec2 near_point_m(0.0, -1e-3 * spec.corridor_length_mm);
  glm::dvec2 tangent = near_point_m / lens.front_vertex_z_m();
  for (int i = 0; i < 40; ++i) {
    const LensRay ray = lens.trace_from_eye(glm::dvec3(tangent, 1.0), kFraunhoferD_nm);
    ASSERT_TRUE(ray.through());
    tangent += (near_point_m - glm::dvec2(ray.origin_m)) / ray.origin_m.z;
  }
  const glm::dvec2 pixel = frame.pixel(glm::dvec3(tangent, 1.0));
  const double down_deg = std::atan(-tangent.y) * kDegPerRad;
  std::printf("near reference point: %.2f deg down, pixel (%.1f, %.1f)\n", down_deg, pixel.x, pixel.y);
  ASSERT_GT(pixel.y, display.height_px / 2 + 100.0);
  const DioptricPower near = eye.error(pixel.x, pixel.y)(0.4);
  const double expected = at_cornea(0.4, 2.0, vertex_m);  // -0.5734 D
  std::printf("E at 0.4 m: ahead %.4f D, near zone mean %.4f D (closed form %.4f D)\n", ahead.mean_dioptres(),
              near.mean_dioptres(), expected);
  // The design's mean power there within 1e-4 D; its astigmatism (-0.05 D) moves the mean carried to
  // the cornea by far less than 5e-3 D.
  EXPECT_NEAR(near.mean_dioptres(), expected, 5e-3);
}

// A +4.00 D single-vision lens (4 mm, base 10 D) 30 deg down: the traced sagittal and tangential
// powers (3.7877 and 3.7819 D at the vertex sphere, which Kakimoto's wavefront tracing, Eq. 4 as
// Coddington's equations, gives too: docs/SPECTACLES.md) carried to the cornea, meridian by
// meridian; straight ahead, the prescription as a thin lens at 12 mm (the session's thin-lens
// refraction, glare/refraction/eye_refraction.h).
TEST(RefractionSessionDepthOfField, ObliqueGazeTakesTheLensPowerAlongIt) {
  SpectacleLensSpec spec;
  spec.prescription.sphere_dioptres = 4.0;
  spec.centre_thickness_mm = 4.0;
  spec.base_curve_dioptres = 10.0;
  const ConditionRefraction refraction = wearing(spec);
  const DisplaySpec display = tall_display();
  const FrameEye eye = frame_eye(refraction, display, std::numeric_limits<double>::infinity());
  const double vertex_m = 1e-3 * spec.vertex_distance_mm;
  const SpectacleFrame frame{display.width_px, display.height_px, display.pixel_pitch_mm / display.viewing_distance_mm * kDegPerRad};

  const DioptricPower ahead = eye.error(display.width_px / 2, display.height_px / 2)(2.0);
  const double thin = vergence_at_cornea(2.0, ThinSpectacleLens{{4.0, 0.0, 0.0}, vertex_m}).mean_dioptres();
  EXPECT_NEAR(ahead.xx(), thin, 2e-3);
  EXPECT_NEAR(ahead.yy(), thin, 2e-3);

  const glm::dvec2 pixel = frame.pixel(glm::dvec3(0.0, -std::tan(30.0 / kDegPerRad), 1.0));
  for (const double distance_m : {std::numeric_limits<double>::infinity(), 2.0}) {
    const DioptricPower down = eye.error(pixel.x, pixel.y)(distance_m);
    std::printf("30 deg down at %.1f m: E xx %.4f (sagittal, closed form %.4f), yy %.4f (tangential, %.4f), xy %.1e\n",
                distance_m, down.xx(), at_cornea(distance_m, 3.7877, vertex_m), down.yy(),
                at_cornea(distance_m, 3.7819, vertex_m), down.xy());
    EXPECT_NEAR(down.xx(), at_cornea(distance_m, 3.7877, vertex_m), 1e-3);
    EXPECT_NEAR(down.yy(), at_cornea(distance_m, 3.7819, vertex_m), 1e-3);
    EXPECT_NEAR(down.xy(), 0.0, 1e-6);
    // Not the power straight ahead: 0.2 D of oblique power error would be lost.
    EXPECT_GT(std::abs(down.xx() - at_cornea(distance_m, 4.0, vertex_m)), 0.15);
  }
}

// --- the two planes, rendered -------------------------------------------------------------

constexpr int kWidth = 160, kHeight = 120;
constexpr float kNearM = 0.4f, kFarM = 2.0f;
constexpr int kLineColumn = 24;  // a bright vertical line on the far plane

bool in_near_plane(int x, int y) { return x >= 64 && x < 144 && y >= 30 && y < 90; }

// A wall at 2 m (20 cd/m2 with a 200 cd/m2 line) and, nearer, a 0.4 m board with a 2 px checkerboard
// over the display centre, where the eye accommodates.
ImageRGBA two_planes() {
  ImageRGBA image(kWidth, kHeight, 1.0f);
  image.depth.assign(static_cast<std::size_t>(kWidth) * kHeight, kFarM);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      float value = x == kLineColumn && y >= 10 && y < 110 ? 200.0f : 20.0f;
      if (in_near_plane(x, y)) {
        value = ((x / 2 + y / 2) % 2 == 0) ? 60.0f : 10.0f;
        image.depth[static_cast<std::size_t>(y) * kWidth + x] = kNearM;
      }
      for (int c = 0; c < 3; ++c) image.pixel(x, y)[c] = value;
    }
  return image;
}

void write_scene(const std::filesystem::path& path, const ImageRGBA& image) {
  ExrWriteOptions options;
  options.write_depth = true;
  write_exr(path.string(), image, options);
}

std::string experiment_toml(const std::string& scene_line, const std::string& observer_extra) {
  return "[experiment]\nname = \"planes\"\nseed = 7\n\n"
         "[display]\nwidth_px = 160\nheight_px = 120\nrefresh_hz = 60.0\nviewing_distance_mm = 400.0\n"
         "pixel_pitch_mm = 0.25\npeak_luminance_cd_m2 = 250.0\nbackground_cd_m2 = 0.0\nencoding = \"srgb\"\n\n"
         "[scenes]\n" + scene_line + "\n\n"
         "[procedure]\ntype = \"rating\"\ncategories = [\"sharpness\"]\nscale_points = 5\nrepetitions = 1\n"
         "stimulus_duration_s = 0.1\n\n"
         "[observer]\nage_years = 20.0\n" + observer_extra + "\n\n[observer.refraction]\nsphere_dioptres = 0.0\n\n"
         "[[conditions.rows]]\nname = \"planes\"\nscene = \"planes\"\nglare_gain = 0.0\n\n"
         "[glare]\nmode = \"static\"\nmodel = \"ritschel\"\ngrid_px = 512\nwavelength_samples = 8\n\n"
         // The frame alone, no question written over the full-frame scene.
         "[presentation]\nquestion_above_stimuli = false\n";
}

// Rendered through a session: the board at the accommodated distance (the centre's depth) is the
// scene itself; the wall is blurred by the uniform disc of its own error, 1 / 0.4 - 1 / 2 = 2 D: its
// line spreads with the disc's second moment R^2 / 4 (R = 2 D x r_p / radians a pixel, r_p from
// Eq. 2 for the frame's mean luminance); and the frame is the depth-of-field stage's output for the
// closed-form eye E(d) = (1 / 0.4 - 1 / d) I. The glare gain is 0, so glare adds nothing.
TEST(RefractionSessionDepthOfField, TwoPlanesRenderedThroughTheSessionEachBlurByTheirOwnDepth) {
  const ScratchDir scratch;
  const ImageRGBA scene = two_planes();
  write_scene(scratch.path() / "planes.exr", scene);
  const auto file = scratch.path() / "planes.toml";
  test::write_bytes(file.string(), experiment_toml("planes = { file = \"planes.exr\" }", ""));
  const auto out = scratch.path() / "frame.exr";
  const auto render = run_glarelab({"render", file.string(), "--condition", "planes", "--out", out.string()}, scratch.path());
  ASSERT_EQ(render.exit_code, 0) << render.output;
  EXPECT_NE(render.output.find("depth of field: accommodated 2.5 D on the centre at 0.4 m"), std::string::npos)
      << render.output;
  const ImageRGBA frame = read_exr(out.string()).image;
  ASSERT_EQ(frame.width_px, kWidth);

  const double pupil_radius_m = 0.5e-3 * moon_spencer_pupil_diameter_mm(mean_luminance(scene));
  const double radians_per_pixel = 0.25 / 400.0;
  DepthOfFieldSettings settings;
  settings.degrees_per_pixel = radians_per_pixel * kDegPerRad;
  settings.pupil_radius_m = pupil_radius_m;
  settings.residual_error = [](double distance_m) { return DioptricPower::spherical(1.0 / 0.4 - 1.0 / distance_m); };
  const ImageRGBA expected = apply_depth_of_field(scene, scene.depth, settings);
  double largest = 0.0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      for (int c = 0; c < 3; ++c)
        largest = std::max(largest, static_cast<double>(std::abs(frame.pixel(x, y)[c] - expected.pixel(x, y)[c])));
  EXPECT_LT(largest, 1e-3) << "the session's frame against the stage with the closed-form eye";

  // The board, away from its edge, is the scene itself: sharp.
  for (int y = 40; y < 80; ++y)
    for (int x = 74; x < 134; ++x) ASSERT_NEAR(frame.pixel(x, y)[1], scene.pixel(x, y)[1], 1e-3) << x << ", " << y;

  // The wall's line: the profile across it (rows 40-80, its excess over the wall) has the uniform
  // disc's variance R^2 / 4 plus the pixel's own 1 / 12.
  const double radius_px = 2.0 * pupil_radius_m / radians_per_pixel;
  double sum = 0.0, second = 0.0;
  for (int y = 40; y < 80; ++y)
    for (int x = 0; x < 60; ++x) {
      const double excess = frame.pixel(x, y)[1] - 20.0;
      sum += excess;
      second += excess * (x - kLineColumn) * (x - kLineColumn);
    }
  const double variance = second / sum;
  std::printf("pupil %.3f mm: wall line variance %.3f px^2, closed form %.3f px^2 (R = %.3f px)\n", 2e3 * pupil_radius_m,
              variance, radius_px * radius_px / 4.0 + 1.0 / 12.0, radius_px);
  EXPECT_NEAR(variance, radius_px * radius_px / 4.0 + 1.0 / 12.0, 0.05 * radius_px * radius_px / 4.0);
  EXPECT_NEAR(sum / 40.0, 180.0, 1.0);  // the line's light is kept
}

// A bad depth stops `glarelab run` before anything is written, naming the file, the channel and
// the pixel; the library refuses NaN, -inf, zero and negative depths the same way.
TEST(RefractionSessionDepthOfField, BadDepthIsRefusedAtLoadNamingTheFileChannelAndPixel) {
  const ScratchDir scratch;
  const std::map<std::string, float> bad{{"NaN", std::numeric_limits<float>::quiet_NaN()},
                                         {"-inf", -std::numeric_limits<float>::infinity()},
                                         {"zero", 0.0f},
                                         {"negative", -1.0f}};
  for (const auto& [problem, value] : bad) {
    ImageRGBA scene = two_planes();
    scene.depth[2 * kWidth + 3] = value;
    const auto path = scratch.path() / ("bad_" + problem + ".exr");
    write_scene(path, scene);
    SceneSpec spec;
    spec.name = "planes";
    spec.file = path.string();
    DisplaySpec display;
    try {
      SceneLibrary library({{"planes", spec}}, display);
      ADD_FAILURE() << problem << " accepted";
    } catch (const ImageError& error) {
      const std::string message = error.what();
      for (const std::string& part : {path.string(), std::string("Z at pixel (3, 2) is ") + problem})
        EXPECT_NE(message.find(part), std::string::npos) << part << " in: " << message;
    }
  }
  // +inf is a surface at infinity: accepted.
  ImageRGBA sky = two_planes();
  sky.depth[0] = std::numeric_limits<float>::infinity();
  write_scene(scratch.path() / "sky.exr", sky);
  SceneSpec spec;
  spec.file = (scratch.path() / "sky.exr").string();
  EXPECT_NO_THROW(SceneLibrary({{"sky", spec}}, DisplaySpec{}));

  const auto file = scratch.path() / "bad.toml";
  test::write_bytes(file.string(), experiment_toml("planes = { file = \"bad_negative.exr\" }", ""));
  const auto db = scratch.path() / "never.db";
  const auto run = run_glarelab({"run", file.string(), "--display", "offscreen", "--observer", "simulated", "--db",
                                 db.string()},
                                scratch.path());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("bad_negative.exr"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("Z at pixel (3, 2) is negative"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(db));
}

// depth_of_field = true asks for depths: a scene without a Z channel is refused, naming it and the
// key; false leaves a scene with Z unblurred.
TEST(RefractionSessionDepthOfField, ExplicitRequestNeedsZAndFalseTurnsItOff) {
  const ScratchDir scratch;
  const auto file = scratch.path() / "lamp.toml";
  test::write_bytes(file.string(),
                    experiment_toml("planes = { generator = \"desk_lamp\", size_px = 100, disc_diameter_deg = 0.1, "
                                    "disc_fraction_of_peak = 0.9 }",
                                    "depth_of_field = true"));
  const auto validate = run_glarelab({"validate", file.string()}, scratch.path());
  EXPECT_EQ(validate.exit_code, 2) << validate.output;
  for (const std::string part : {"observer.depth_of_field", "scene 'planes'", "has no Z channel", "lamp.toml:"})
    EXPECT_NE(validate.output.find(part), std::string::npos) << part << " in: " << validate.output;

  write_scene(scratch.path() / "planes.exr", two_planes());
  const auto off = scratch.path() / "off.toml";
  test::write_bytes(off.string(), experiment_toml("planes = { file = \"planes.exr\" }", "depth_of_field = false"));
  const auto out = scratch.path() / "frame.exr";
  const auto render = run_glarelab({"render", off.string(), "--condition", "planes", "--out", out.string()}, scratch.path());
  ASSERT_EQ(render.exit_code, 0) << render.output;
  EXPECT_EQ(render.output.find("depth of field"), std::string::npos) << render.output;
  const ImageRGBA frame = read_exr(out.string()).image;
  EXPECT_NEAR(frame.pixel(kLineColumn, 60)[1], 200.0f, 1e-3);  // the line stays sharp
}

}  // namespace
}  // namespace glarelab

// `[glare] straylight`: the human eye's CIE far field scaled to a participant's straylight
// (docs/STRAYLIGHT.md). A session's rendered veil 7 degrees from a small lamp is the lamp's
// illuminance at the eye times 10^log(s) / 7^2 (the definition of s); the key is read strictly,
// checked against the observer's pigmentation and stored in the resolved configuration.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "cli_process.h"
#include "core/exr_io.h"
#include "protocols/experiment.h"
#include "display_directions.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

constexpr int kWidthPx = 256, kHeightPx = 160;
constexpr double kDistanceMm = 300.0, kPitchMm = 0.5;
constexpr float kLampCdM2 = 1e6f;

std::string lamp_experiment(const std::string& straylight_line) {
  return R"([experiment]
name = "straylight-lamp"
seed = 3

[display]
width_px = 256
height_px = 160
viewing_distance_mm = 300.0
pixel_pitch_mm = 0.5
peak_luminance_cd_m2 = 250.0
background_cd_m2 = 100.0

[observer]
age_years = 25.0
pigmentation = 0.5

[glare]
)" + straylight_line + R"(

[scenes]
lamp = { file = "lamp.exr" }

[procedure]
type = "rating"
categories = ["glare"]
stimulus_frames = 1

[presentation]
question_above_stimuli = false

[[conditions.rows]]
name = "glare"
scene = "lamp"
glare = "dynamic"

[[conditions.rows]]
name = "control"
scene = "lamp"
glare = "control"
)";
}

const test::DisplayDirections kDisplay{kWidthPx, kHeightPx, kPitchMm, kDistanceMm};

// Acceptance 3: with straylight = 1.4 the veil 7 degrees from the lamp is E x 10^1.4 / 7^2 within
// 10 % (the CIE eye of age 25 alone gives about 10^0.84 / 7^2, a factor 3.6 less). At 7 degrees the
// ciliary corona's lines (glare/analytic/ciliary_corona.h) move single pixels by tens of percent
// and keep each ring's mean, so the veil is the mean over the whole 1-pixel ring about the lamp
// (74 px in radius: the display is 160 px tall, the lamp 100 px from its left edge); the
// background, 100 cd/m2 like the field's mean, keeps the pupil under 3 mm (no lenticular halo).
TEST(StraylightGlare, VeilAtSevenDegreesIsTheIlluminanceTimesTheMeasuredStraylight) {
  test::ScratchDir dir;
  ImageRGBA scene(kWidthPx, kHeightPx, 0.0f);
  for (int y = 79; y < 81; ++y)
    for (int x = 99; x < 101; ++x)
      for (int c = 0; c < 3; ++c) scene.pixel(x, y)[c] = kLampCdM2;
  write_exr((dir.path() / "lamp.exr").string(), scene);
  const std::string experiment = dir.write("experiment.toml", lamp_experiment("straylight = 1.4"));
  const auto render = [&](const std::string& condition) {
    const auto out = dir.path() / (condition + ".exr");
    const auto run = test::run_glarelab({"render", experiment, "--condition", condition, "--time", "0.5", "--out", out.string()},
                                        dir.path());
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return read_exr(out.string()).image;
  };
  const ImageRGBA glare = render("glare"), control = render("control");
  ASSERT_EQ(glare.width_px, kWidthPx);
  const double lamp_x = 99.5, lamp_y = 79.5;
  const int row = 79;
  int best_x = -1;
  double best_error = 1e300;
  for (int x = 100; x < kWidthPx; ++x) {
    const double error = std::abs(kDisplay.angle_between_pixels_deg(lamp_x, lamp_y, x, row) - 7.0);
    if (error < best_error) best_error = error, best_x = x;
  }
  ASSERT_LT(best_error, 0.05);
  double illuminance_lx = 0.0;
  for (int y = 79; y < 81; ++y)
    for (int x = 99; x < 101; ++x) illuminance_lx += kLampCdM2 * kDisplay.pixel_solid_angle_sr(x, y);
  const double angle_deg = kDisplay.angle_between_pixels_deg(lamp_x, lamp_y, best_x, row);
  // The ring's mean veil, and the mean of E x 10^1.4 / theta^2 at its pixels' own angles.
  const long ring = std::lround(std::hypot(best_x - lamp_x, row - lamp_y));
  double veil_sum = 0.0, expected_sum = 0.0;
  int pixels = 0;
  for (int y = 0; y < kHeightPx; ++y)
    for (int x = 0; x < kWidthPx; ++x) {
      if (std::lround(std::hypot(x - lamp_x, y - lamp_y)) != ring) continue;
      ASSERT_TRUE(x > 0 && y > 0 && x < kWidthPx - 1 && y < kHeightPx - 1) << "the ring leaves the display";
      const double theta = kDisplay.angle_between_pixels_deg(lamp_x, lamp_y, x, y);
      veil_sum += static_cast<double>(glare.pixel(x, y)[1]) - control.pixel(x, y)[1];
      expected_sum += illuminance_lx * std::pow(10.0, 1.4) / (theta * theta);
      ++pixels;
    }
  const double expected_cd_m2 = expected_sum / pixels, veil_cd_m2 = veil_sum / pixels;
  std::printf("straylight 1.4: %.3f deg from the lamp (E = %.5g lx): veil %.5g cd/m2, E x 10^1.4 / 49 = %.5g (ratio %.4f)\n",
              angle_deg, illuminance_lx, veil_cd_m2, expected_cd_m2, veil_cd_m2 / expected_cd_m2);
  EXPECT_NEAR(veil_cd_m2 / expected_cd_m2, 1.0, 0.10);
}

std::string config_error(const std::string& text) {
  try {
    parse_experiment_text(text, "s.toml", "/tmp");
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "no error";
}

TEST(StraylightGlare, KeyIsReadCheckedAndStoredInTheResolvedConfig) {
  const Experiment e = parse_experiment_text(lamp_experiment("straylight = 1.25"), "s.toml", "/tmp");
  ASSERT_TRUE(e.glare.observer_eye.straylight_log_s.has_value());
  EXPECT_EQ(*e.glare.observer_eye.straylight_log_s, 1.25);
  EXPECT_EQ(e.glare.observer_eye.age_years, 25.0);
  const std::string resolved = resolved_config_toml(e);
  EXPECT_NE(resolved.find("straylight = 1.25"), std::string::npos) << resolved;
  const Experiment reread = parse_experiment_text(resolved, "<stored config>", "/");
  EXPECT_EQ(reread.glare.observer_eye.straylight_log_s, e.glare.observer_eye.straylight_log_s);
  EXPECT_FALSE(parse_experiment_text(lamp_experiment(""), "s.toml", "/tmp").glare.observer_eye.straylight_log_s);

  // Out of bounds either way, and with more than all the light scattered: each refused at the
  // key's line (line 18 of the file).
  for (const std::string value : {"3.5", "0.3"}) {
    const std::string bound = config_error(lamp_experiment("straylight = " + value));
    EXPECT_NE(bound.find("s.toml:18"), std::string::npos) << bound;
    EXPECT_NE(bound.find("glare.straylight"), std::string::npos) << bound;
  }
  const std::string too_much = config_error(lamp_experiment("straylight = 2.4"));
  EXPECT_NE(too_much.find("s.toml:18"), std::string::npos) << too_much;
  EXPECT_NE(too_much.find("scatters"), std::string::npos) << too_much;
  EXPECT_NE(config_error(lamp_experiment("straylight = \"high\"")).find("glare.straylight"), std::string::npos);
}

}  // namespace
}  // namespace glarelab

// glarelab render: the control frame is the composed stimulus (the scenes placed side by side on
// the background, nothing else, with the question switched off), dynamic glare conserves the frame's luminance when nothing falls
// off its edge, and the PNG preview decodes to the display encoding of the frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "cli_process.h"
#include "lamp_scene.h"
#include "scratch_dir.h"
#include "stimuli/display_model.h"
#include "core/exr_io.h"
#include "core/png_io.h"

namespace glarelab {
namespace {

using test::write_lamp_scene;

std::string experiment_text() {
  return R"([experiment]
name = "render-test"
seed = 42

[display]
width_px = 128
height_px = 64
peak_luminance_cd_m2 = 250.0

[scenes]
dim = { file = "dim.exr" }
bright = { file = "bright.exr" }

[procedure]
type = "forced_choice"
stimulus_frames = 2
counterbalance_sides = false  # scene_a on the left in every trial

[presentation]
question_above_stimuli = false  # the frame holds the scenes alone, so it can be composed by hand

[glare]
grid_px = 128
wavelength_samples = 8
model = "ritschel"  # the wave-optics eye alone: nothing falls off the frame's edge, so luminance is conserved

[[conditions.rows]]
name = "plain"
scene_a = "dim"
scene_b = "bright"
glare = "control"

[[conditions.rows]]
name = "moving"
scene_a = "dim"
scene_b = "bright"
glare = "dynamic"
)";
}

double luminance_sum(const ImageRGBA& image) {
  double sum = 0.0;
  for (std::size_t i = 0; i < image.rgba.size(); i += 4)
    sum += luminance_rec709(image.rgba[i], image.rgba[i + 1], image.rgba[i + 2]);
  return sum;
}

class RenderCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    write_lamp_scene((dir.path() / "dim.exr").string(), 80.0f);
    write_lamp_scene((dir.path() / "bright.exr").string(), 200.0f);
    experiment = dir.write("experiment.toml", experiment_text());
  }
  ImageRGBA render(const std::vector<std::string>& extra, const std::string& out) {
    std::vector<std::string> arguments = {"render", experiment, "--out", (dir.path() / out).string()};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    const test::RunOutput result = test::run_glarelab(arguments, dir.path());
    EXPECT_EQ(result.exit_code, 0) << result.output;
    std::printf("%s", result.output.c_str());
    return out.ends_with(".png") ? read_png_encoded((dir.path() / out).string()) : read_exr((dir.path() / out).string()).image;
  }
  test::ScratchDir dir;
  std::string experiment;
};

TEST_F(RenderCommand, ControlIsTheComposedStimulusAndDynamicConservesLuminance) {
  const ImageRGBA control = render({"--condition", "plain", "--time", "0.5"}, "control.exr");
  ASSERT_EQ(control.width_px, 128);
  ASSERT_EQ(control.height_px, 64);
  // Composed by hand: two 64-px columns, each 32-px scene centred -> lamps at x 30..33 and 94..97,
  // y 30..33; everything else is the 0 cd/m2 background.
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 128; ++x) {
      const bool in_y = y >= 30 && y < 34;
      const float expected = in_y && x >= 30 && x < 34 ? 80.0f : in_y && x >= 94 && x < 98 ? 200.0f : 0.0f;
      ASSERT_EQ(control.pixel(x, y)[0], expected) << x << "," << y;
    }
  // The dynamic condition with its glare switched off is the same composed frame, bit for bit.
  const ImageRGBA off = render({"--condition", "moving", "--time", "0.5", "--glare", "control"}, "off.exr");
  EXPECT_EQ(off.rgba, control.rgba);

  const ImageRGBA dynamic = render({"--condition", "moving", "--time", "0.5"}, "dynamic.exr");
  EXPECT_NE(dynamic.rgba, control.rgba);
  EXPECT_NEAR(luminance_sum(dynamic) / luminance_sum(control), 1.0, 1e-3);
  EXPECT_LT(dynamic.pixel(95, 31)[1], 200.0f);  // the lamp loses light to its surround
  EXPECT_GT(dynamic.pixel(90, 31)[1], 0.0f);
}

TEST_F(RenderCommand, PngPreviewIsTheDisplayEncodedFrame) {
  const ImageRGBA png = render({"--condition", "plain", "--time", "0"}, "preview.png");
  ASSERT_EQ(png.width_px, 128);
  ASSERT_EQ(png.height_px, 64);
  DisplaySpec display;  // the test experiment keeps the default sRGB encoding, peak 250
  display.peak_luminance_cd_m2 = 250.0;
  const DisplayModel model(display);
  EXPECT_NEAR(png.pixel(31, 31)[0], model.encode(80.0), 0.5 / 255.0 + 1e-6);
  EXPECT_NEAR(png.pixel(95, 31)[0], model.encode(200.0), 0.5 / 255.0 + 1e-6);
  EXPECT_EQ(png.pixel(5, 5)[0], 0.0f);
}

TEST_F(RenderCommand, UnknownConditionIsRefusedWithTheNamesThereAre) {
  const test::RunOutput result = test::run_glarelab(
      {"render", experiment, "--condition", "nope", "--out", (dir.path() / "x.exr").string()}, dir.path());
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.output.find("'plain', 'moving'"), std::string::npos) << result.output;
}

// Largest R value in the columns [x0, x1) of a frame, over its middle half of rows (the scenes of
// the examples, below the question text): the peak of the scene shown there.
float column_peak(const ImageRGBA& image, int x0, int x1) {
  float peak = 0.0f;
  for (int y = image.height_px / 4; y < 3 * image.height_px / 4; ++y)
    for (int x = x0; x < x1; ++x) peak = std::max(peak, image.pixel(x, y)[0]);
  return peak;
}

std::string example(const std::string& file) { return std::string(GLARELAB_SOURCE_DIR) + "/examples/" + file; }

// A staircase trial at a chosen intensity: the comparison disc peaks at it, the reference (the
// light source) keeps its own 150 cd/m2 (75 % of the 200 cd/m2 peak); without --intensity the
// track's start (100 cd/m2).
TEST_F(RenderCommand, StaircaseAtAGivenIntensityScalesTheComparisonOnly) {
  const auto peaks = [&](const std::vector<std::string>& extra, const std::string& out) {
    std::vector<std::string> arguments = {"--condition", "alone_01", "--glare", "control"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    std::vector<std::string> full = {"render", example("spencer_staircase.toml"), "--out", (dir.path() / out).string()};
    full.insert(full.end(), arguments.begin(), arguments.end());
    const test::RunOutput result = test::run_glarelab(full, dir.path());
    EXPECT_EQ(result.exit_code, 0) << result.output;
    const ImageRGBA frame = read_exr((dir.path() / out).string()).image;
    std::vector<float> sides = {column_peak(frame, 0, frame.width_px / 2),
                                column_peak(frame, frame.width_px / 2, frame.width_px)};
    std::sort(sides.begin(), sides.end());
    return sides;
  };
  EXPECT_EQ(peaks({}, "start.exr"), (std::vector<float>{100.0f, 150.0f}));
  const std::vector<float> chosen = peaks({"--intensity", "180"}, "chosen.exr");
  ASSERT_EQ(chosen.size(), 2u);
  EXPECT_EQ(chosen[0], 150.0f);
  EXPECT_NEAR(chosen[1], 180.0f, 180.0f * 1e-6f);
}

// Spencer's glare image with its glare (gain 2.5, Spencer's photopic filter, glare_keeps_peak):
// its brightest pixel stays at the source's 75 % of the 200 cd/m2 peak while its halo spreads;
// the disc on the other side is drawn without glare.
TEST_F(RenderCommand, SpencerGlareImageKeepsItsPeakAtThreeQuartersOfTheDisplay) {
  const std::string out = (dir.path() / "glare_image.exr").string();
  const test::RunOutput result = test::run_glarelab(
      {"render", example("spencer_staircase.toml"), "--condition", "alone_12", "--intensity", "100", "--out", out},
      dir.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("gain 2.5, glared peak kept"), std::string::npos) << result.output;
  const ImageRGBA frame = read_exr(out).image;
  std::vector<float> sides = {column_peak(frame, 0, frame.width_px / 2), column_peak(frame, frame.width_px / 2, frame.width_px)};
  std::sort(sides.begin(), sides.end());
  EXPECT_NEAR(sides[0], 100.0f, 0.05f);  // the disc at the chosen intensity, but for the glare image's far spill
  EXPECT_NEAR(sides[1], 150.0f, 150.0f * 1e-5f);  // the glare image's maximum
  // The halo: 20 px (about half a degree) beside the source, light where the drawn scene is black.
  const int glare_side = frame.pixel(frame.width_px / 4, frame.height_px / 2)[0] > 120.0f ? 0 : 1;
  const int cx = frame.width_px / 4 + glare_side * frame.width_px / 2, cy = frame.height_px / 2;
  EXPECT_GT(frame.pixel(cx + 20, cy)[0], 0.5f);
  EXPECT_GT(frame.pixel(cx, cy)[0], 140.0f);  // the centre is the source's brightest part
}

// An adjustment trial at given settings: the left and right spots at them, the target (lamp_130)
// in the centre as it is.
TEST_F(RenderCommand, AdjustmentAtGivenSettingsShowsTheSpotsAtThem) {
  const std::string out = (dir.path() / "adjustment.exr").string();
  const test::RunOutput result =
      test::run_glarelab({"render", example("ritschel_adjustment.toml"), "--condition", "control_low", "--settings",
                          "50", "300", "--out", out},
                         dir.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("spots at 50 and 300 cd/m2"), std::string::npos) << result.output;
  const ImageRGBA frame = read_exr(out).image;
  const int third = frame.width_px / 3;
  EXPECT_NEAR(column_peak(frame, 0, third), 50.0f, 50.0f * 1e-6f);
  EXPECT_NEAR(column_peak(frame, third, 2 * third), 130.0f, 130.0f * 1e-6f);
  EXPECT_NEAR(column_peak(frame, 2 * third, frame.width_px), 300.0f, 300.0f * 1e-6f);
}

// An intensity for a design without a comparison is refused, saying what it applies to.
TEST_F(RenderCommand, IntensityForAFixedDesignIsRefused) {
  const test::RunOutput result =
      test::run_glarelab({"render", experiment, "--condition", "plain", "--intensity", "120", "--out",
                          (dir.path() / "x.exr").string()},
                         dir.path());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("an intensity applies to staircase and QUEST"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "x.exr"));
}

}  // namespace
}  // namespace glarelab

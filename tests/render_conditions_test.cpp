// glarelab render of several conditions in one pass (--condition again, or --all-conditions, into
// --out-dir): each frame equals the frame rendered for its condition alone, bit for bit (that
// preview stops at its frame; this one runs the session on to the next condition), a condition
// the seeded session never shows is named, and the options that change a trial are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_process.h"
#include "lamp_scene.h"
#include "core/exr_io.h"
#include "core/png_io.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

using test::write_lamp_scene;

// Three conditions over six trials in a seeded order (held/still first, then plain, then moving);
// the dynamic eye and the perception stages' eye see every frame, so a frame captured after
// another depends on the whole history before it, the captured trial's own frames included (had
// the first capture's trial stopped at its first frame, moving's frame would differ).
constexpr const char* kExperiment = R"([experiment]
name = "render-conditions-test"
seed = 7

[display]
width_px = 128
height_px = 64
peak_luminance_cd_m2 = 250.0

[scenes]
dim = { file = "dim.exr" }
bright = { file = "bright.exr" }

[procedure]
type = "forced_choice"
stimulus_frames = 12
repetitions = 2

[glare]
grid_px = 128
wavelength_samples = 8

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
perception = "all"

[[conditions.rows]]
name = "held/still"
scene_a = "bright"
scene_b = "dim"
glare = "dynamic"
perception = "all"
)";

class RenderConditions : public ::testing::Test {
 protected:
  void SetUp() override {
    write_lamp_scene((dir.path() / "dim.exr").string(), 80.0f);
    write_lamp_scene((dir.path() / "bright.exr").string(), 200.0f);
    experiment = (dir.path() / "experiment.toml").string();
    std::ofstream(experiment) << kExperiment;
  }
  test::ScratchDir dir;
  std::string experiment;
};

bool same_values(const ImageRGBA& a, const ImageRGBA& b) {
  return a.width_px == b.width_px && a.height_px == b.height_px && a.rgba == b.rgba;
}

TEST_F(RenderConditions, EachFrameOfOnePassIsTheFrameRenderedAlone) {
  const auto folder = dir.path() / "frames";
  const test::RunOutput all =
      test::run_glarelab({"render", experiment, "--all-conditions", "--out-dir", folder.string()}, dir.path());
  ASSERT_EQ(all.exit_code, 0) << all.output;
  EXPECT_NE(all.output.find("3 of 3 conditions written"), std::string::npos) << all.output;
  // A name that is no file name is written with '_' for what a file name cannot hold.
  for (const auto& [condition, file] : std::vector<std::pair<std::string, std::string>>{
           {"plain", "plain"}, {"moving", "moving"}, {"held/still", "held_still"}}) {
    SCOPED_TRACE(condition);
    const auto alone_exr = dir.path() / (file + "_alone.exr"), alone_png = dir.path() / (file + "_alone.png");
    for (const auto& out : {alone_exr, alone_png}) {
      const test::RunOutput one =
          test::run_glarelab({"render", experiment, "--condition", condition, "--out", out.string()}, dir.path());
      ASSERT_EQ(one.exit_code, 0) << one.output;
    }
    const ImageRGBA frame = read_exr((folder / (file + ".exr")).string()).image;
    EXPECT_TRUE(same_values(frame, read_exr(alone_exr.string()).image));
    EXPECT_TRUE(same_values(read_png_encoded((folder / (file + ".png")).string()), read_png_encoded(alone_png.string())));
    double peak = 0.0;
    for (float value : frame.rgba) peak = std::max(peak, static_cast<double>(value));
    EXPECT_GE(peak, 80.0);  // a scene is in it
  }
  // Repeated --condition is the same pass as --all-conditions.
  const auto two = dir.path() / "two";
  const test::RunOutput some = test::run_glarelab(
      {"render", experiment, "--condition", "moving", "--condition", "plain", "--out-dir", two.string()}, dir.path());
  ASSERT_EQ(some.exit_code, 0) << some.output;
  EXPECT_NE(some.output.find("2 of 2 conditions written"), std::string::npos) << some.output;
  EXPECT_TRUE(same_values(read_exr((two / "moving.exr").string()).image, read_exr((folder / "moving.exr").string()).image));
  EXPECT_FALSE(std::filesystem::exists(two / "held_still.exr"));
}

// QUEST+ picks its own rows: the seeded session of the example never shows lamp_130 (its track
// picks lamp_160), so one pass writes the other two and names it; alone it is shown as its track
// would show it (tests/render_every_row_test.cpp).
TEST_F(RenderConditions, ARowTheSeededSessionNeverShowsIsNamed) {
  const auto folder = dir.path() / "quest";
  const test::RunOutput all = test::run_glarelab(
      {"render", std::string(GLARELAB_SOURCE_DIR) + "/examples/glare_quest_plus.toml", "--all-conditions", "--out-dir",
       folder.string()},
      dir.path());
  ASSERT_EQ(all.exit_code, 0) << all.output;
  EXPECT_NE(all.output.find("2 of 3 conditions written"), std::string::npos) << all.output;
  EXPECT_NE(all.output.find("the seeded session shows no trial of 'lamp_130'"), std::string::npos) << all.output;
  EXPECT_TRUE(std::filesystem::is_regular_file(folder / "lamp_160.exr"));
  EXPECT_FALSE(std::filesystem::exists(folder / "lamp_130.exr"));
}

TEST_F(RenderConditions, OptionsForOneConditionAreRefusedForSeveralBeforeAnythingIsWritten) {
  const std::string out = (dir.path() / "x.exr").string(), folder = (dir.path() / "refused").string();
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--condition", "plain", "--condition", "moving", "--out", out}, "for several conditions give --out-dir"},
      {{"--all-conditions", "--out", out}, "for several conditions give --out-dir"},
      {{"--all-conditions", "--glare", "control", "--out-dir", folder}, "they are for one condition"},
      {{"--condition", "plain", "--condition", "moving", "--time", "1", "--out-dir", folder}, "they are for one condition"},
      {{"--out", out}, "give --condition NAME (once or more) or --all-conditions"},
      {{"--condition", "plain", "--out", out, "--out-dir", folder}, "give --out FILE (one condition) or --out-dir"},
      {{"--condition", "plain", "--all-conditions", "--out-dir", folder}, "--condition excludes --all-conditions"},
      {{"--condition", "plain", "--condition", "nope", "--out-dir", folder}, "unknown condition 'nope'"},
  };
  for (const auto& [arguments, message] : cases) {
    std::vector<std::string> full = {"render", experiment};
    full.insert(full.end(), arguments.begin(), arguments.end());
    const test::RunOutput result = test::run_glarelab(full, dir.path());
    EXPECT_EQ(result.exit_code, 2) << result.output;
    EXPECT_NE(result.output.find(message), std::string::npos) << result.output;
  }
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(folder));
}

}  // namespace
}  // namespace glarelab

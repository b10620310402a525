// glarelab render of a condition row that a seeded session never shows (issue 33): QUEST+ picks a
// track's row together with the intensity, and in glare_quest_plus.toml the increment track never
// picks lamp_130 in the sessions of participants 1-4. A user previewing the design must still see
// that row's frame, told what was changed to show it; a row that no session can show is refused
// with the reason.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "cli_process.h"
#include "core/exr_io.h"
#include "core/image.h"

namespace glarelab {
namespace {

const std::string kQuestPlus = std::string(GLARELAB_SOURCE_DIR) + "/examples/glare_quest_plus.toml";

// Largest luminance (cd/m2) in columns [x0, x1) of a frame's middle half of rows, where the scenes
// are (the question is drawn above them, at the text luminance).
double max_luminance_in_columns(const ImageRGBA& image, int x0, int x1) {
  double peak = 0.0;
  for (int y = image.height_px / 4; y < 3 * image.height_px / 4; ++y)
    for (int x = x0; x < x1; ++x) {
      const std::size_t i = 4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width_px) + static_cast<std::size_t>(x));
      peak = std::max(peak, luminance_rec709(image.rgba[i], image.rgba[i + 1], image.rgba[i + 2]));
    }
  return peak;
}

TEST(RenderEveryRow, AQuestPlusRowItsTrackNeverPicksIsRenderedAndTheChangeSaid) {
  const test::ScratchDir scratch;
  const auto out = scratch.path() / "lamp_130.exr";
  const auto result = test::run_glarelab(
      {"render", kQuestPlus, "--condition", "lamp_130", "--intensity", "40", "--out", out.string()}, scratch.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;  // was 2: "not shown in a session of participant number 1"
  EXPECT_NE(result.output.find("render: condition 'lamp_130', trial "), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("comparison at 40 cd/m2"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("note: track 'increment_function' chose condition '"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("shown with condition 'lamp_130' in its place"), std::string::npos) << result.output;

  // The frame shows the row's own scenes: its reference, lamp_130, at the scene file's peak on one
  // side, and its comparison scaled to the asked 40 cd/m2 on the other (no glare in this file).
  const ImageRGBA frame = read_exr(out.string()).image;
  const double reference_cd_m2 =
      max_luminance(read_exr(std::string(GLARELAB_SOURCE_DIR) + "/examples/scenes/lamp_130.exr").image);
  ASSERT_GT(reference_cd_m2, 100.0);
  const double left = max_luminance_in_columns(frame, 0, frame.width_px / 2);
  const double right = max_luminance_in_columns(frame, frame.width_px / 2, frame.width_px);
  const double brighter = std::max(left, right), dimmer = std::min(left, right);
  EXPECT_NEAR(brighter, reference_cd_m2, 1e-3 * reference_cd_m2) << "left " << left << ", right " << right;
  EXPECT_NEAR(dimmer, 40.0, 1e-3 * 40.0) << "left " << left << ", right " << right;
}

TEST(RenderEveryRow, ARowTheTrackPicksItselfIsRenderedWithoutANote) {
  const test::ScratchDir scratch;
  const auto out = scratch.path() / "lamp_100.png";
  const auto result =
      test::run_glarelab({"render", kQuestPlus, "--condition", "lamp_100", "--out", out.string()}, scratch.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output.find("note: track"), std::string::npos) << result.output;
  EXPECT_TRUE(std::filesystem::exists(out));
}

TEST(RenderEveryRow, ARowNoTrackShowsIsRefusedWithTheReason) {
  const test::ScratchDir scratch;
  // A staircase whose one track names its row: a second row is in the table but in no track.
  std::string text = test::read_bytes(kQuestPlus);
  text += "\n[[conditions.rows]]\nname = \"spare\"\nreference = \"lamp_160\"\ncomparison = \"lamp_100\"\n"
          "reference_gain_db = 9.0\n";
  std::filesystem::copy(std::string(GLARELAB_SOURCE_DIR) + "/examples/scenes", scratch.path() / "scenes");
  const std::string experiment = scratch.write("spare.toml", text);
  const auto out = scratch.path() / "spare.png";
  const auto result =
      test::run_glarelab({"render", experiment, "--condition", "spare", "--out", out.string()}, scratch.path());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("condition 'spare' cannot be previewed: no track of the quest_plus procedure shows it "
                               "(the tracks show 'lamp_100', 'lamp_100', 'lamp_130', 'lamp_160')"),
            std::string::npos)
      << result.output;
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace glarelab

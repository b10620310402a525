// Placement you can read and trust (issue: a lab's first study): side-by-side columns spaced by
// [display] stimulus_gap_deg; a scene larger than its column refused at validate with its size and
// its place named, unless its entry says fit = "scale" (the whole scene, area-averaged) or "crop".
// The new user's study rebuilt: a 1240 px and a 928 px scene side by side on a 1920 px display.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "cli_process.h"
#include "core/exr_io.h"
#include "scratch_dir.h"
#include "stimuli/layout.h"
#include "stimuli/scene_fit.h"

namespace glarelab {
namespace {

TEST(ScenePlacement, ColumnsAreSpacedByTheGap) {
  std::vector<PixelRect> columns;
  const auto placed = side_by_side_layout(1920, 1080, {{0, 0, 100, 50}, {0, 0, 200, 60}}, &columns, 42);
  ASSERT_EQ(columns.size(), 2u);
  // (1920 - 42) / 2 = 939 px each, the second starting 42 px after the first ends.
  EXPECT_EQ(columns[0].x_px, 0);
  EXPECT_EQ(columns[0].width_px, 939);
  EXPECT_EQ(columns[1].x_px, 981);
  EXPECT_EQ(columns[1].width_px, 939);
  EXPECT_EQ(placed[1].x_px, 981 + (939 - 200) / 2);
  EXPECT_EQ(placed[1].y_px, (1080 - 60) / 2);
  // Without a gap the columns tile the screen, as before.
  columns.clear();
  side_by_side_layout(1920, 1080, {{0, 0, 1, 1}, {0, 0, 1, 1}, {0, 0, 1, 1}}, &columns);
  EXPECT_EQ(columns[1].x_px, 640);
  EXPECT_EQ(columns[2].x_px + columns[2].width_px, 1920);
  EXPECT_THROW(side_by_side_layout(100, 10, {{0, 0, 1, 1}, {0, 0, 1, 1}}, nullptr, 99), std::invalid_argument);
}

TEST(ScenePlacement, AreaAveragingKeepsEachBoxsMean) {
  // One row 1, 2, 3 onto 2 px: boxes of 1.5 px, (1 + 0.5 * 2) / 1.5 and (0.5 * 2 + 3) / 1.5.
  ImageRGBA row(3, 1, 0.0f);
  for (int x = 0; x < 3; ++x) row.pixel(x, 0)[0] = static_cast<float>(x + 1);
  const ImageRGBA scaled = scale_image_down(row, 2, 1);
  EXPECT_NEAR(scaled.pixel(0, 0)[0], 4.0 / 3.0, 1e-6);
  EXPECT_NEAR(scaled.pixel(1, 0)[0], 8.0 / 3.0, 1e-6);
  // A 7 x 5 ramp onto 3 x 2: the mean is kept (the boxes tile the input).
  ImageRGBA ramp(7, 5, 0.0f);
  double sum = 0.0;
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 7; ++x) sum += ramp.pixel(x, y)[1] = static_cast<float>(x * x + 3 * y);
  const ImageRGBA small = scale_image_down(ramp, 3, 2);
  double small_sum = 0.0;
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) small_sum += small.pixel(x, y)[1];
  EXPECT_NEAR(small_sum / 6.0, sum / 35.0, 1e-5);
  const FitSize size = scaled_fit_size(1240, 846, 939, 1080);
  EXPECT_EQ(size.width_px, 939);
  EXPECT_EQ(size.height_px, static_cast<int>(std::floor(846.0 * 939.0 / 1240.0)));
  ImageRGBA with_depth(4, 4, 1.0f);
  with_depth.depth.assign(16, 2.0f);
  EXPECT_THROW(scale_image_down(with_depth, 2, 2), std::invalid_argument);
  const ImageRGBA cropped = crop_image_centre(ramp, 3, 3);
  EXPECT_EQ(cropped.pixel(0, 0)[1], ramp.pixel(2, 1)[1]);
}

// A scene of `width_px` x `height_px` at `fill_cd_m2` with a one-pixel border at `border_cd_m2`:
// its edges show whether it is shown whole.
void write_bordered_scene(const std::string& path, int width_px, int height_px, float fill_cd_m2, float border_cd_m2) {
  ImageRGBA image(width_px, height_px, fill_cd_m2);
  for (int y = 0; y < height_px; ++y)
    for (int x = 0; x < width_px; ++x)
      if (x == 0 || y == 0 || x == width_px - 1 || y == height_px - 1)
        for (int c = 0; c < 3; ++c) image.pixel(x, y)[c] = border_cd_m2;
  write_exr(path, image);
}

std::string study(const std::string& fit, double gap_deg) {
  return "[experiment]\nname = \"first-study\"\nseed = 5\n\n[display]\nwidth_px = 1920\nheight_px = 1080\n"
         "viewing_distance_mm = 600.0\npixel_pitch_mm = 0.25\npeak_luminance_cd_m2 = 250.0\nstimulus_gap_deg = " +
         std::to_string(gap_deg) + "\n\n[scenes]\nstill_life = { file = \"still_life.exr\"" + fit +
         " }\ntree = { file = \"tree.exr\"" + fit +
         " }\n\n[procedure]\ntype = \"forced_choice\"\nstimulus_frames = 2\ncounterbalance_sides = false\n\n"
         "[presentation]\nquestion_above_stimuli = false\n\n[glare]\nmode = \"control\"\n\n"
         "[[conditions.rows]]\nname = \"pair\"\nscene_a = \"still_life\"\nscene_b = \"tree\"\n";
}

class FirstStudy : public ::testing::Test {
 protected:
  void SetUp() override {
    write_bordered_scene(dir.file("still_life.exr"), 1240, 846, 10.0f, 100.0f);
    write_bordered_scene(dir.file("tree.exr"), 928, 906, 20.0f, 100.0f);
  }
  test::ScratchDir dir;
};

TEST_F(FirstStudy, ASceneWiderThanItsColumnIsRefusedWithTheSizesNamed) {
  const std::string experiment = dir.write("study.toml", study("", 0.0));
  const test::RunOutput result = test::run_glarelab({"validate", experiment}, dir.path());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("study.toml:"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("scene 'still_life' (1240 x 846 px) does not fit"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("960 x 1080 px"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("1920 x 1080 px"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("fit = \"scale\""), std::string::npos) << result.output;
}

TEST_F(FirstStudy, WithFitScaleBothScenesAreShownWholeAGapApart) {
  const double gap_deg = 1.0;
  const std::string experiment = dir.write("study.toml", study(", fit = \"scale\"", gap_deg));
  const test::RunOutput validate = test::run_glarelab({"validate", experiment}, dir.path());
  ASSERT_EQ(validate.exit_code, 0) << validate.output;
  EXPECT_NE(validate.output.find("scene 'still_life' (1240 x 846 px) scaled to"), std::string::npos) << validate.output;
  const test::RunOutput render =
      test::run_glarelab({"render", experiment, "--condition", "pair", "--out", dir.file("frame.exr")}, dir.path());
  ASSERT_EQ(render.exit_code, 0) << render.output;
  const ImageRGBA frame = read_exr(dir.file("frame.exr")).image;
  ASSERT_EQ(frame.width_px, 1920);

  // The places by hand: the gap 2 d tan(1 deg / 2) / pitch, rounded; two columns of the rest.
  const int gap_px = static_cast<int>(std::lround(2.0 * 600.0 * std::tan(0.5 * gap_deg * std::numbers::pi / 180.0) / 0.25));
  const int column_px = (1920 - gap_px) / 2;
  const int scaled_w = column_px, scaled_h = static_cast<int>(std::floor(846.0 * column_px / 1240.0));
  const int a_x = 0, a_y = (1080 - scaled_h) / 2;
  const int b_x = column_px + gap_px + (column_px - 928) / 2, b_y = (1080 - 906) / 2;
  const auto y_at = [&](int x, int y) { return frame.pixel(x, y)[1]; };
  // Every edge of each scene is in the frame (the border, area-averaged into the scaled one's edge
  // pixels at 1 / (1240 / scaled_w) or 1 / (846 / scaled_h) of its box at least), and nothing of
  // it lies outside.
  const double border_share = std::min(scaled_w / 1240.0, scaled_h / 846.0);
  const auto edge_min = static_cast<float>(10.0 + 90.0 * border_share - 0.01);
  for (int y = a_y; y < a_y + scaled_h; ++y) {
    ASSERT_GE(y_at(a_x, y), edge_min) << y;
    ASSERT_GE(y_at(a_x + scaled_w - 1, y), edge_min) << y;
  }
  for (int x = a_x; x < a_x + scaled_w; ++x) {
    ASSERT_GE(y_at(x, a_y), edge_min) << x;
    ASSERT_GE(y_at(x, a_y + scaled_h - 1), edge_min) << x;
    ASSERT_EQ(y_at(x, a_y - 1), 0.0f) << x;
    ASSERT_EQ(y_at(x, a_y + scaled_h), 0.0f) << x;
  }
  for (int y = b_y; y < b_y + 906; ++y) {
    ASSERT_EQ(y_at(b_x, y), 100.0f) << y;
    ASSERT_EQ(y_at(b_x + 927, y), 100.0f) << y;
    ASSERT_EQ(y_at(b_x - 1, y), 0.0f) << y;
    ASSERT_EQ(y_at(b_x + 928, y), 0.0f) << y;
  }
  // The gap is background.
  for (int x = column_px; x < column_px + gap_px; ++x) ASSERT_EQ(y_at(x, 540), 0.0f) << x;
  // Area averaging keeps the scaled scene's mean luminance: the original's, by hand.
  const double original_mean = (100.0 * (2 * 1240 + 2 * 844) + 10.0 * 1238.0 * 844.0) / (1240.0 * 846.0);
  double sum = 0.0;
  for (int y = a_y; y < a_y + scaled_h; ++y)
    for (int x = a_x; x < a_x + scaled_w; ++x) sum += y_at(x, y);
  EXPECT_NEAR(sum / (static_cast<double>(scaled_w) * scaled_h), original_mean, 1e-3);
}

TEST_F(FirstStudy, WithFitCropTheCentreFillsTheColumn) {
  const std::string experiment = dir.write("study.toml", study(", fit = \"crop\"", 0.0));
  const test::RunOutput render =
      test::run_glarelab({"render", experiment, "--condition", "pair", "--out", dir.file("frame.exr")}, dir.path());
  ASSERT_EQ(render.exit_code, 0) << render.output;
  EXPECT_NE(render.output.find("cropped to its centre 960 x 846 px"), std::string::npos) << render.output;
  const ImageRGBA frame = read_exr(dir.file("frame.exr")).image;
  // 140 px cut from each side: the left and right borders are gone, the top and bottom kept.
  const int y0 = (1080 - 846) / 2;
  EXPECT_EQ(frame.pixel(0, 540)[1], 10.0f);
  EXPECT_EQ(frame.pixel(959, 540)[1], 10.0f);
  EXPECT_EQ(frame.pixel(480, y0)[1], 100.0f);
  EXPECT_EQ(frame.pixel(480, y0 + 845)[1], 100.0f);
}

}  // namespace
}  // namespace glarelab

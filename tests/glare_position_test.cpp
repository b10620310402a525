// Glare per position (stimuli/position_glare.h): layers sharing one mode give the whole-frame
// glare (convolution is linear), the eye adapts to the whole frame, a control layer keeps its own
// light, and each glared layer keeps its energy.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <tuple>
#include <utility>

#include "stimuli/position_glare.h"

namespace glarelab {
namespace {

GlareSpec small_spec() {
  GlareSpec spec;
  spec.model = GlareModel::ritschel;  // the wave-optics eye alone, whose behaviour these checks state
  spec.backend = GlareBackendRequest::cpu;
  spec.grid_px = 128;
  spec.wavelength_samples = 8;
  return spec;
}

DisplaySpec small_display() {
  DisplaySpec display;
  display.width_px = 128;
  display.height_px = 64;
  return display;
}

// Two lamps, left (x 24..31) and right (x 96..103), rows 28..35, on black; each alone as a layer.
struct TwoLamps {
  ImageRGBA composed{128, 64, 0.0f};
  ImageRGBA left{128, 64, 0.0f};
  ImageRGBA right{128, 64, 0.0f};
  TwoLamps(float left_cd_m2, float right_cd_m2) {
    for (int y = 28; y < 36; ++y)
      for (int x = 0; x < 8; ++x)
        for (int c = 0; c < 3; ++c) {
          composed.pixel(24 + x, y)[c] = left.pixel(24 + x, y)[c] = left_cd_m2;
          composed.pixel(96 + x, y)[c] = right.pixel(96 + x, y)[c] = right_cd_m2;
        }
  }
};

double relative_l2(const ImageRGBA& a, const ImageRGBA& b) {
  double difference = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < a.rgba.size(); ++i) {
    if (i % 4 == 3) continue;
    difference += std::pow(double(a.rgba[i]) - b.rgba[i], 2);
    norm += std::pow(double(b.rgba[i]), 2);
  }
  return std::sqrt(difference / norm);
}

double sum_over(const ImageRGBA& image, int x0, int x1, int channel) {
  double sum = 0.0;
  for (int y = 0; y < image.height_px; ++y)
    for (int x = x0; x < x1; ++x) sum += image.pixel(x, y)[channel];
  return sum;
}

TEST(PositionGlare, LayersSharingAModeGiveTheWholeFrameGlare) {
  const TwoLamps lamps(400.0f, 250.0f);
  for (const GlareMode mode : {GlareMode::static_eye, GlareMode::dynamic}) {
    GlareStage whole_stage(small_spec(), small_display(), 11);
    GlareStage layered_stage(small_spec(), small_display(), 11);
    const ImageRGBA whole = whole_stage.apply(lamps.composed, mode, 0.4);
    const ImageRGBA layered =
        apply_layered_glare(layered_stage, lamps.composed, {{lamps.left, mode}, {lamps.right, mode}}, 0.4, std::nullopt);
    EXPECT_LT(relative_l2(layered, whole), 1e-6) << to_string(mode);
    EXPECT_GT(relative_l2(whole, lamps.composed), 1e-3) << "glare must change the frame for the test to mean anything";
  }
}

TEST(PositionGlare, ControlSideKeepsItsLightAndTheGlaredSideKeepsItsEnergy) {
  const TwoLamps lamps(400.0f, 400.0f);
  GlareStage stage(small_spec(), small_display(), 5);
  std::vector<GlareFrameReport> reports;
  const ImageRGBA out = apply_layered_glare(stage, lamps.composed, {{lamps.left, GlareMode::static_eye},
                                                                     {lamps.right, GlareMode::control}},
                                            0.0, std::nullopt, &reports);
  ASSERT_EQ(reports.size(), 1u);  // one report per glared layer
  EXPECT_TRUE(reports[0].convolved);
  // The static (left) lamp spreads: its centre loses light. The control (right) lamp is untouched
  // but for the left lamp's spill, 64 px away.
  EXPECT_LT(out.pixel(27, 31)[1], 0.99f * 400.0f);
  EXPECT_NEAR(out.pixel(99, 31)[1], 400.0f, 0.01 * 400.0);
  // Energy: the left half holds the left lamp's glared light; the frame holds both lamps' light.
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(sum_over(out, 0, 128, c) / sum_over(lamps.composed, 0, 128, c), 1.0, 1e-5) << "channel " << c;
    EXPECT_GT(sum_over(out, 0, 64, c), sum_over(lamps.composed, 0, 64, c) * 0.99) << "channel " << c;
  }
}

TEST(PositionGlare, TheEyeAdaptsToTheWholeFrameNotToOneLayer) {
  // A dim left lamp next to a bright right one: the layered left glare uses the pupil of the
  // whole frame's mean, which is what a static eye adapted to the whole frame shows.
  const TwoLamps lamps(50.0f, 5000.0f);
  GlareStage layered_stage(small_spec(), small_display(), 2);
  std::vector<GlareFrameReport> reports;
  apply_layered_glare(layered_stage, lamps.composed, {{lamps.left, GlareMode::static_eye}, {lamps.right, GlareMode::control}},
                      0.0, std::nullopt, &reports);
  GlareStage whole_stage(small_spec(), small_display(), 2);
  GlareFrameReport whole_report, left_alone_report;
  whole_stage.apply(lamps.composed, GlareMode::static_eye, 0.0, &whole_report);
  GlareStage left_stage(small_spec(), small_display(), 2);
  left_stage.apply(lamps.left, GlareMode::static_eye, 0.0, &left_alone_report);
  ASSERT_EQ(reports.size(), 1u);
  EXPECT_EQ(reports[0].pupil_diameter_mm, whole_report.pupil_diameter_mm);
  EXPECT_GT(left_alone_report.pupil_diameter_mm, whole_report.pupil_diameter_mm + 0.1);  // darker field: wider pupil
}

// keep_peak (Spencer 1995, section 4: the glare image peaks at 75 % of the display whatever its
// glare): the glared layer is the glare of the layer drawn brighter by (peak before) / (peak
// after), so its brightest pixel stays where it was, while the unscaled one dims as the gain
// spreads more of the core into the halo.
TEST(PositionGlare, AKeptPeakIsTheGlareOfABrighterSource) {
  const TwoLamps lamps(150.0f, 100.0f);
  GlareSpec spec = small_spec();
  spec.model = GlareModel::spencer;
  spec.spencer_regime = SpencerRegime::photopic;
  // The layers are glared with the eye adapted to the whole frame: so are the references here.
  const double field_cd_m2 = mean_luminance(lamps.composed);
  double previous_centre = 150.0;
  for (const double gain : {0.5, 1.0, 2.0}) {
    GlareStage stage(spec, small_display(), 3);
    stage.set_condition(GlareModel::spencer, gain);
    const ImageRGBA kept = apply_layered_glare(
        stage, lamps.composed, {{lamps.left, GlareMode::static_eye, true}, {lamps.right, GlareMode::control}}, 0.0,
        std::nullopt);
    GlareStage plain_stage(spec, small_display(), 3);
    plain_stage.set_condition(GlareModel::spencer, gain);
    const ImageRGBA plain = plain_stage.apply(lamps.left, GlareMode::static_eye, 0.0, nullptr, std::nullopt, field_cd_m2);
    const double unscaled_peak = max_luminance(plain);
    EXPECT_LT(plain.pixel(27, 31)[1], previous_centre) << "gain " << gain << ": more glare, a dimmer centre";
    previous_centre = plain.pixel(27, 31)[1];
    // The left half: the glared left lamp, peaking at its drawn 150 cd/m2.
    double kept_peak = 0.0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) kept_peak = std::max(kept_peak, luminance_rec709(kept.pixel(x, y)[0], kept.pixel(x, y)[1], kept.pixel(x, y)[2]));
    EXPECT_NEAR(kept_peak, 150.0, 150.0 * 1e-5) << "gain " << gain;
    // ... and it is the glare of the lamp drawn brighter: the same glare, scaled.
    const double scale = 150.0 / unscaled_peak;
    GlareStage bright_stage(spec, small_display(), 3);
    bright_stage.set_condition(GlareModel::spencer, gain);
    ImageRGBA brighter = lamps.left;
    for (std::size_t i = 0; i < brighter.rgba.size(); ++i)
      if (i % 4 != 3) brighter.rgba[i] = static_cast<float>(brighter.rgba[i] * scale);
    const ImageRGBA bright = bright_stage.apply(brighter, GlareMode::static_eye, 0.0, nullptr, std::nullopt, field_cd_m2);
    EXPECT_NEAR(kept.pixel(27, 31)[1], bright.pixel(27, 31)[1], 1e-3 * 150.0) << "gain " << gain;
    EXPECT_NEAR(kept.pixel(40, 31)[1], bright.pixel(40, 31)[1], 1e-3 * 150.0) << "gain " << gain;
    // The control side is untouched.
    EXPECT_NEAR(kept.pixel(99, 31)[1], 100.0f, 2.0f);  // but for the left lamp's spill, 64 px away
  }
}

// A static layer's glare kept from frame to frame: frames of a dynamic lamp beside a static one
// equal those computed afresh, bit for bit, with the static layer convolved once (its kept report
// counts as an application each frame); a new gaze or field luminance computes it again. The sum's
// base kept with it (StaticLayerGlare::SumBase) holds the kept glare where the static layer comes
// first in the sum and only the layers' difference where the dynamic one does: both orders.
// The wave-optics eye's glare says where it changed each layer, so the sum is made in those boxes;
// the default eye's veil reaches the whole frame, and the sum is made everywhere from the base.
class PositionGlareKept : public ::testing::TestWithParam<std::tuple<GlareModel, bool>> {};

TEST_P(PositionGlareKept, AStaticLayersKeptGlareGivesTheFramesComputedAfresh) {
  const TwoLamps lamps(400.0f, 250.0f);
  const auto [model, static_first] = GetParam();
  std::vector<GlareLayer> layers = {{lamps.left, GlareMode::dynamic}, {lamps.right, GlareMode::static_eye, true}};
  if (static_first) std::swap(layers[0], layers[1]);
  const std::size_t dynamic = static_first ? 1 : 0, still = 1 - dynamic;
  GlareSpec spec = small_spec();
  spec.model = model;
  const bool everywhere = model == GlareModel::human;
  GlareStage fresh_stage(spec, small_display(), 11);
  GlareStage kept_stage(spec, small_display(), 11);
  StaticLayerGlare kept;
  const std::vector<std::optional<GazePoint>> gazes = {std::nullopt, std::nullopt, GazePoint{0.3, 0.5}, GazePoint{0.3, 0.5}};
  // Where the kept glare's pixels live: the same buffer while it is reused, a new one when made again.
  std::vector<const float*> kept_pixels;
  for (std::size_t frame = 0; frame < gazes.size(); ++frame) {
    const double time_s = 0.4 + static_cast<double>(frame) / 60.0;
    std::vector<GlareFrameReport> fresh_reports, kept_reports;
    const ImageRGBA fresh = apply_layered_glare(fresh_stage, lamps.composed, layers, time_s, gazes[frame], &fresh_reports);
    const ImageRGBA reused =
        apply_layered_glare(kept_stage, lamps.composed, layers, time_s, gazes[frame], &kept_reports, std::nullopt, &kept);
    EXPECT_EQ(fresh.rgba, reused.rgba) << "frame " << frame;
    ASSERT_EQ(kept_reports.size(), 2u);
    EXPECT_EQ(fresh_reports.size(), kept_reports.size());
    ASSERT_TRUE(kept.layers.at(still).has_value());
    EXPECT_FALSE(kept.layers.at(dynamic).has_value()) << "a dynamic layer's glare changes every frame: never kept";
    EXPECT_EQ(kept.layers[still]->gaze.has_value(), gazes[frame].has_value());
    kept_pixels.push_back(kept.layers[still]->glared_cd_m2.rgba.data());
    if (everywhere) {
      EXPECT_EQ(kept.base.kept_serials.size(), static_first ? 1u : 0u) << "frame " << frame;
      EXPECT_EQ(kept.base.glaring.size(), 2u);
    } else {
      EXPECT_TRUE(kept.base.glaring.empty()) << "made in the boxes, from no base";
    }
  }
  EXPECT_EQ(kept_pixels[1], kept_pixels[0]) << "the same gaze: reused";
  EXPECT_NE(kept_pixels[2], kept_pixels[1]) << "a new gaze: computed again";
  EXPECT_EQ(kept_pixels[3], kept_pixels[2]);
  // A different field luminance is not the kept one's: computed again, as afresh.
  const ImageRGBA fresh = apply_layered_glare(fresh_stage, lamps.composed, layers, 0.5, std::nullopt, nullptr, 3.0);
  const ImageRGBA reused = apply_layered_glare(kept_stage, lamps.composed, layers, 0.5, std::nullopt, nullptr, 3.0, &kept);
  EXPECT_EQ(fresh.rgba, reused.rgba);
  EXPECT_EQ(kept.layers[still]->field_luminance_cd_m2, 3.0);
}

INSTANTIATE_TEST_SUITE_P(BothOrders, PositionGlareKept,
                         ::testing::Combine(::testing::Values(GlareModel::ritschel, GlareModel::human), ::testing::Bool()),
                         [](const ::testing::TestParamInfo<std::tuple<GlareModel, bool>>& param) {
                           return std::string(std::get<0>(param.param) == GlareModel::human ? "DefaultEye" : "Ritschel") +
                                  (std::get<1>(param.param) ? "StaticLayerFirst" : "DynamicLayerFirst");
                         });

// The sum of the layers' glare is made only where the glare changed them (the reports' boxes);
// everywhere it must be the per-value sum composed - left - right + glared left + glared right of
// the layers glared one by one, bit for bit, including the background between and around the boxes.
TEST(PositionGlare, TheSumIsMadeWhereTheGlareChangedAndIsTheWholeSumEverywhere) {
  const TwoLamps lamps(400.0f, 250.0f);
  ImageRGBA composed = lamps.composed;
  for (std::size_t i = 0; i < composed.rgba.size(); ++i)
    if (i % 4 != 3 && composed.rgba[i] == 0.0f) composed.rgba[i] = 0.5f;  // a grey background
  const std::vector<GlareLayer> layers = {{lamps.left, GlareMode::dynamic}, {lamps.right, GlareMode::static_eye}};
  GlareStage stage(small_spec(), small_display(), 11), reference_stage(small_spec(), small_display(), 11);
  std::vector<GlareFrameReport> reports;
  const ImageRGBA result = apply_layered_glare(stage, composed, layers, 0.4, std::nullopt, &reports);
  const double field_cd_m2 = mean_luminance(composed);
  const ImageRGBA left = reference_stage.apply(lamps.left, GlareMode::dynamic, 0.4, nullptr, std::nullopt, field_cd_m2);
  const ImageRGBA right = reference_stage.apply(lamps.right, GlareMode::static_eye, 0.4, nullptr, std::nullopt, field_cd_m2);
  ImageRGBA expected = composed;
  for (std::size_t i = 0; i < expected.rgba.size(); ++i)
    if (i % 4 != 3) expected.rgba[i] = composed.rgba[i] - lamps.left.rgba[i] - lamps.right.rgba[i] + left.rgba[i] + right.rgba[i];
  EXPECT_EQ(result.rgba, expected.rgba);
  EXPECT_GT(relative_l2(result, composed), 1e-3) << "glare must change the frame for the test to mean anything";
  // The boxes the sum was confined to: each lamp's grown by the PSF's reach, far less than the frame.
  ASSERT_EQ(reports.size(), 2u);
  for (const GlareFrameReport& report : reports) {
    ASSERT_TRUE(report.changed_boxes.has_value());
    ASSERT_EQ(report.changed_boxes->size(), 1u);
    const PixelRect& box = report.changed_boxes->front();
    EXPECT_LT(box.width_px * box.height_px, 128 * 64 / 2);
    EXPECT_GT(box.width_px, 8);
  }
  // Outside the reports' boxes the result is the composed frame, bit for bit: what a session takes
  // as given when it looks for the changed rectangle only inside them (runner/session/trial_glare.cpp).
  std::size_t outside = 0;
  for (int y = 0; y < composed.height_px; ++y)
    for (int x = 0; x < composed.width_px; ++x) {
      bool inside = false;
      for (const GlareFrameReport& report : reports)
        for (const PixelRect& box : *report.changed_boxes)
          inside |= x >= box.x_px && x < box.x_px + box.width_px && y >= box.y_px && y < box.y_px + box.height_px;
      if (inside) continue;
      ++outside;
      for (int c = 0; c < 4; ++c) ASSERT_EQ(result.pixel(x, y)[c], composed.pixel(x, y)[c]) << x << ", " << y;
    }
  EXPECT_GT(outside, 0u);
}

TEST(PositionGlare, ALayerOfAnotherSizeIsRefused) {
  const TwoLamps lamps(100.0f, 100.0f);
  GlareStage stage(small_spec(), small_display(), 1);
  EXPECT_THROW(apply_layered_glare(stage, lamps.composed, {{ImageRGBA(64, 64), GlareMode::static_eye}}, 0.0, std::nullopt),
               std::invalid_argument);
}

}  // namespace
}  // namespace glarelab

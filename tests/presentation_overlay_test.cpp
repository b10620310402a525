// Text and the fixation cross drawn over a finished (glared) frame, read back from the stimulus
// framebuffer of the offscreen (OSMesa) renderer: the question sits above the stimuli, its pixels
// reach the text luminance, and nothing else of the frame changes.
#include <gtest/gtest.h>

#include <algorithm>

#include "runner/display/display_backend.h"
#include "runner/session/presentation_overlays.h"
#include "stimuli/frame_renderer.h"

namespace glarelab {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 160;

Experiment small_experiment() {
  Experiment experiment;
  experiment.display.width_px = kWidth;
  experiment.display.height_px = kHeight;
  experiment.display.viewing_distance_mm = 600.0;
  experiment.display.pixel_pitch_mm = 0.25;
  experiment.presentation.text_height_deg = 0.4;  // 2 x 600 x tan(0.2 deg) / 0.25 = 16.76 -> 17 px
  experiment.presentation.text_cd_m2 = 100.0;
  experiment.presentation.fixation_size_deg = 0.5;  // 20.9 -> 21 px
  return experiment;
}

std::unique_ptr<DisplayBackend> offscreen() {
  DisplayRequest request;
  request.width_px = kWidth;
  request.height_px = kHeight;
  return create_display("offscreen", request);
}

bool inside(const PixelRect& rect, int x, int y) {
  return x >= rect.x_px && x < rect.x_px + rect.width_px && y >= rect.y_px && y < rect.y_px + rect.height_px;
}

TEST(PresentationOverlay, QuestionIsDrawnAboveTheStimuliOverTheGlaredFrame) {
  const auto display = offscreen();
  FrameRenderer renderer(kWidth, kHeight);
  const Experiment experiment = small_experiment();
  PresentationOverlays overlays(renderer, experiment);
  EXPECT_EQ(overlays.line_height_px(), 17);

  // A 40 x 40 source of 40 cd/m2 in the middle of a black screen.
  ImageRGBA square(40, 40, 40.0f);
  const SceneTexture scene = renderer.upload(square);
  const PixelRect stimulus{140, 60, 40, 40};
  renderer.compose({{&scene, 1.0, stimulus, {0, 0, kWidth, kHeight}}}, 0.0);
  // Stand-in for the glare stage: the composed frame plus a 2 cd/m2 veil everywhere.
  ImageRGBA glared = renderer.read_stimulus();
  for (std::size_t i = 0; i < glared.rgba.size(); i += 4)
    for (std::size_t c = 0; c < 3; ++c) glared.rgba[i + c] += 2.0f;
  renderer.replace_stimulus(glared);

  const std::vector<Placement> question = overlays.question("Brighter?", {stimulus});
  ASSERT_EQ(question.size(), 1u);
  const PixelRect text = question[0].rect;
  // Centred, its bottom half a line (8 px) above the stimulus.
  EXPECT_EQ(text.y_px + text.height_px, stimulus.y_px - 8);
  EXPECT_EQ(text.x_px, (kWidth - text.width_px) / 2);
  EXPECT_GT(text.width_px, 3 * overlays.line_height_px()) << "nine glyphs";
  renderer.compose_overlay(question);
  const ImageRGBA frame = renderer.read_stimulus();

  float brightest_in_text = 0.0f, darkest_in_text = 1e9f;
  int text_pixels = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const float value = frame.pixel(x, y)[1];
      const float before = glared.pixel(x, y)[1];
      if (inside(text, x, y)) {
        brightest_in_text = std::max(brightest_in_text, value);
        darkest_in_text = std::min(darkest_in_text, value);
        text_pixels += value > before + 1e-3f ? 1 : 0;
      } else {
        // Outside the text's rectangle the glared frame is untouched: no clear, no blending.
        ASSERT_EQ(value, before) << "at " << x << "," << y;
      }
    }
  }
  EXPECT_NEAR(brightest_in_text, 100.0f, 1e-3f) << "fully covered glyph pixels show the text luminance";
  EXPECT_NEAR(darkest_in_text, 2.0f, 1e-4f) << "the veil stays visible between the glyphs";
  EXPECT_GT(text_pixels, 50);
  EXPECT_LT(text_pixels, text.width_px * text.height_px / 2);
}

TEST(PresentationOverlay, FixationCrossAndFeedbackAreCentred) {
  const auto display = offscreen();
  FrameRenderer renderer(kWidth, kHeight);
  PresentationOverlays overlays(renderer, small_experiment());
  EXPECT_EQ(overlays.fixation_size_px(), 21);
  renderer.compose({}, 1.0);
  renderer.compose_overlay(overlays.fixation());
  const ImageRGBA frame = renderer.read_stimulus();
  // The 21 px cross at x 149..169, y 69..89 ((320 - 21) / 2, (160 - 21) / 2), centre (159, 79),
  // arms 3 px thick (21 / 8 = 2, made odd): on along both arms, off between and beyond them.
  EXPECT_EQ(frame.pixel(159, 79)[0], 100.0f);
  EXPECT_EQ(frame.pixel(149, 79)[0], 100.0f);
  EXPECT_EQ(frame.pixel(169, 79)[0], 100.0f);
  EXPECT_EQ(frame.pixel(159, 69)[0], 100.0f);
  EXPECT_EQ(frame.pixel(159, 89)[0], 100.0f);
  EXPECT_EQ(frame.pixel(160, 80)[0], 100.0f);
  EXPECT_EQ(frame.pixel(161, 81)[0], 1.0f) << "between the arms: background";
  EXPECT_EQ(frame.pixel(170, 79)[0], 1.0f) << "beyond the arm";
  EXPECT_EQ(frame.pixel(159, 90)[0], 1.0f);
  EXPECT_EQ(frame.pixel(149, 69)[0], 1.0f);

  const std::vector<Placement> feedback = overlays.centred_text("correct");
  ASSERT_EQ(feedback.size(), 1u);
  EXPECT_EQ(feedback[0].rect.x_px, (kWidth - feedback[0].rect.width_px) / 2);
  EXPECT_EQ(feedback[0].rect.y_px, (kHeight - feedback[0].rect.height_px) / 2);
  EXPECT_TRUE(overlays.centred_text("").empty());
}

TEST(PresentationOverlay, QuestionCanBeSwitchedOff) {
  const auto display = offscreen();
  FrameRenderer renderer(kWidth, kHeight);
  Experiment experiment = small_experiment();
  experiment.presentation.question_above_stimuli = false;
  PresentationOverlays overlays(renderer, experiment);
  EXPECT_TRUE(overlays.question("Brighter?", {{140, 60, 40, 40}}).empty());
}

}  // namespace
}  // namespace glarelab

// The perception stages in Fig. 6.1's order (Luidolt 2020), their switches and the validation.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "glare/eye/pupil_model.h"
#include "stimuli/perception/perception_stages.h"

namespace glarelab {
namespace {

ImageRGBA night_scene() {
  // A dark street (0.005-0.05 cd/m2 texture) with a 200 cd/m2 lamp.
  ImageRGBA scene(64, 48, 0.0f);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      float* p = scene.pixel(x, y);
      const float base = ((x / 3 + y / 2) % 2 == 0) ? 0.05f : 0.005f;
      p[0] = base * 0.8f;
      p[1] = base;
      p[2] = base * 1.3f;
      p[3] = 1.0f;
    }
  for (int y = 10; y < 14; ++y)
    for (int x = 40; x < 44; ++x) {
      float* p = scene.pixel(x, y);
      p[0] = 220.0f;
      p[1] = 200.0f;
      p[2] = 150.0f;
    }
  return scene;
}

bool same_pixels(const ImageRGBA& a, const ImageRGBA& b) { return a.width_px == b.width_px && a.rgba == b.rgba; }

TEST(PerceptionStages, RunInFigure61Order) {
  const ImageRGBA scene = night_scene();
  DisplaySpec display;
  PerceptionSettings settings;
  TemporalAdaptation eye(0.5);
  const PerceptionFrameInput input{0.4, 0.6, 1.0 / 90.0};
  // Glare here: a uniform veil of 0.01 cd/m2 (any operation on cd/m2 will do).
  std::vector<std::string> seen;
  const PerceptionGlare glare = [&](const ImageRGBA& image) {
    seen.push_back("glare");
    ImageRGBA out = image;
    for (std::size_t i = 0; i < out.rgba.size(); i += 4)
      for (int c = 0; c < 3; ++c) out.rgba[i + c] += 0.01f;
    return out;
  };
  const PerceptionResult result = run_perception_stages(scene, input, eye, settings, display, glare);
  const std::vector<PerceptionStage> order = {PerceptionStage::adaptation, PerceptionStage::glare, PerceptionStage::acuity,
                                              PerceptionStage::tone_mapping, PerceptionStage::scotopic};
  EXPECT_EQ(result.stages_run, order);
  ASSERT_EQ(seen.size(), 1u);

  // The same by hand, stage by stage: adaptation on the scene before glare (5.1), acuity on the glared
  // cd/m2, tone mapping with L_i, the scotopic shift after it with sigma(L_i).
  const double frame_luminance = frame_adaptation_luminance_cd_m2(scene, 0.4, 0.6);
  EXPECT_EQ(result.frame_luminance_cd_m2, frame_luminance);
  const double adapted = adapted_luminance_after_cd_m2(0.5, frame_luminance, 1.0 / 90.0,
                                                       adaptation_time_constant_s(frame_luminance, 0.4, 0.1, 0.04));
  EXPECT_NEAR(result.adapted_luminance_cd_m2, adapted, 1e-15);
  EXPECT_EQ(eye.adapted_luminance_cd_m2(), result.adapted_luminance_cd_m2);
  const double ppd = display_pixels_per_degree(display);
  const ImageRGBA by_hand = apply_scotopic_colour(
      tone_map(apply_acuity_loss(glare(scene), settings.acuity_settings, ppd), adapted, settings.tone_mapping_settings,
               display.peak_luminance_cd_m2),
      0.04 / (0.04 + adapted), settings.scotopic_settings);
  EXPECT_TRUE(same_pixels(result.image, by_hand));
  // The order matters: scotopic before tone mapping gives another frame.
  const ImageRGBA swapped = tone_map(
      apply_scotopic_colour(apply_acuity_loss(glare(scene), settings.acuity_settings, ppd), 0.04 / (0.04 + adapted),
                            settings.scotopic_settings),
      adapted, settings.tone_mapping_settings, display.peak_luminance_cd_m2);
  EXPECT_FALSE(same_pixels(result.image, swapped));
}

TEST(PerceptionStages, SwitchesTurnStagesOff) {
  const ImageRGBA scene = night_scene();
  DisplaySpec display;
  PerceptionSettings off;
  off.adaptation = off.glare = off.acuity = off.tone_mapping = off.scotopic = false;
  TemporalAdaptation eye(7.0);
  const PerceptionResult result = run_perception_stages(scene, {0.5, 0.5, 0.1}, eye, off, display);
  EXPECT_TRUE(result.stages_run.empty());
  EXPECT_TRUE(same_pixels(result.image, scene));
  // Adaptation off: instant adaptation to the frame, the eye left alone.
  EXPECT_EQ(result.adapted_luminance_cd_m2, result.frame_luminance_cd_m2);
  EXPECT_EQ(eye.adapted_luminance_cd_m2(), 7.0);
  // Glare on without a glare stage: skipped.
  PerceptionSettings glare_only = off;
  glare_only.glare = true;
  EXPECT_TRUE(run_perception_stages(scene, {0.5, 0.5, 0.1}, eye, glare_only, display).stages_run.empty());
  // Tone curve none with the other stages off: the clip at the peak.
  PerceptionSettings clip = off;
  clip.tone_mapping = true;
  clip.tone_mapping_settings.curve = ToneCurve::none;
  display.peak_luminance_cd_m2 = 100.0;
  const PerceptionResult clipped = run_perception_stages(scene, {0.5, 0.5, 0.1}, eye, clip, display);
  EXPECT_EQ(clipped.image.pixel(41, 11)[0], 100.0f);
  EXPECT_EQ(clipped.image.pixel(0, 0)[1], scene.pixel(0, 0)[1]);
}

std::string message_of(const PerceptionSettings& settings) {
  try {
    validate_perception_settings(settings);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(PerceptionStages, ValidationNamesTheFieldAndTheRange) {
  PerceptionSettings settings;
  EXPECT_EQ(message_of(settings), "");
  settings.acuity_settings.max_sigma_px = 20.0;
  std::string message = message_of(settings);
  EXPECT_NE(message.find("[acuity]"), std::string::npos) << message;
  EXPECT_NE(message.find("max_sigma_px must be in (0, 10]"), std::string::npos) << message;
  settings = {};
  settings.adaptation_weighting.gaze_sigma_frame_widths = -1.0;
  message = message_of(settings);
  EXPECT_NE(message.find("gaze_sigma_frame_widths must be in (0, 10]"), std::string::npos) << message;
  settings = {};
  settings.adaptation_time_constants.cone_time_constant_s = 0.0;
  EXPECT_NE(message_of(settings).find("cone_time_constant_s"), std::string::npos);
  settings = {};
  settings.scotopic_settings.spencer_saturation_reduction = -0.1;
  EXPECT_NE(message_of(settings).find("spencer_saturation_reduction must be in [0, 1]"), std::string::npos);
  settings = {};
  settings.tone_mapping_settings.minimum_adapted_luminance_cd_m2 = 0.0;
  EXPECT_NE(message_of(settings).find("minimum_adapted_luminance_cd_m2"), std::string::npos);

  // A session refuses the bad settings before touching the eye.
  PerceptionSettings bad;
  bad.acuity_settings.reference_white_cd_m2 = 0.0;
  TemporalAdaptation eye(1.0);
  EXPECT_THROW(run_perception_stages(night_scene(), {}, eye, bad, DisplaySpec{}), std::invalid_argument);
  EXPECT_EQ(eye.adapted_luminance_cd_m2(), 1.0);
  // An eye made with other time constants than the settings' is refused.
  PerceptionSettings slower;
  slower.adaptation_time_constants.rod_time_constant_s = 0.8;
  EXPECT_THROW(run_perception_stages(night_scene(), {}, eye, slower, DisplaySpec{}), std::invalid_argument);
}

TEST(PerceptionStages, ParsersNameTheFieldAndTheAcceptedValues) {
  EXPECT_EQ(parse_tone_curve("aces_narkowicz"), ToneCurve::aces_narkowicz);
  EXPECT_EQ(parse_tone_curve("none"), ToneCurve::none);
  EXPECT_EQ(parse_tone_curve("aces_hill"), ToneCurve::aces_hill);
  EXPECT_EQ(parse_scotopic_form("spencer_desaturation"), ScotopicForm::spencer_desaturation);
  EXPECT_EQ(parse_acuity_sigma_form("luidolt_linear"), AcuitySigmaForm::luidolt_linear);
  EXPECT_EQ(parse_second_pass_sigma("original_lightness"), SecondPassSigma::original_lightness);
  try {
    parse_tone_curve("aces");
    FAIL() << "'aces' was accepted";
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("tone_curve must be one of \"aces_narkowicz\", \"aces_hill\", \"none\" (got 'aces')"),
              std::string::npos)
        << message;
  }
  EXPECT_THROW(parse_scotopic_form("purkinje"), std::invalid_argument);
  EXPECT_THROW(parse_acuity_sigma_form(""), std::invalid_argument);
  EXPECT_THROW(parse_second_pass_sigma("both"), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab

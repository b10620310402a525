// A session's perception stages (stimuli/session_perception.h): the glare between adaptation and
// acuity is computed for the eye the adaptation stage says (its field luminance the adapted
// luminance, Luidolt 2020 Fig. 6.1 and section 5.1), the session's eye advances exactly for any
// split of the time into frames (Eq. 5.2), and sees the background between frames.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "stimuli/glare_stage.h"
#include "stimuli/session_perception.h"

namespace glarelab {
namespace {

DisplaySpec small_display() {
  DisplaySpec display;
  display.width_px = 96;
  display.height_px = 64;
  display.background_cd_m2 = 0.0;
  return display;
}

// A dim surround with a bright square in the middle.
ImageRGBA lamp_frame(float surround_cd_m2, float lamp_cd_m2) {
  ImageRGBA frame(96, 64, surround_cd_m2);
  for (int y = 28; y < 36; ++y)
    for (int x = 44; x < 52; ++x)
      for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = lamp_cd_m2;
  return frame;
}

PerceptionSettings only(bool adaptation) {
  PerceptionSettings settings;
  settings.adaptation = adaptation;
  settings.acuity = false;
  settings.tone_mapping = false;
  settings.scotopic = false;
  return settings;
}

TEST(SessionPerception, AdaptationDrivesTheGlaresFieldLuminance) {
  const DisplaySpec display = small_display();
  GlareSpec spec;
  spec.model = GlareModel::ritschel;  // the wave-optics eye alone, whose behaviour these checks state
  spec.backend = GlareBackendRequest::cpu;
  spec.grid_px = 128;
  spec.wavelength_samples = 8;
  spec.skip_invisible = false;
  GlareStage glare(spec, display, 7);
  const double period_s = 1.0 / 60.0;
  const ImageRGBA dark = lamp_frame(0.01f, 0.01f);
  const ImageRGBA lit = lamp_frame(50.0f, 2000.0f);

  for (const bool adaptation : {true, false}) {
    SessionPerception perception(AdaptationTimeConstants{}, display);
    // The eye adapts to the dark frame first, then the lamp comes on.
    perception.process(dark, only(adaptation), 0.0, period_s, 0.5, 0.5);
    std::optional<double> field_seen;
    bool glare_ran = false;
    const FieldGlare field_glare = [&](const ImageRGBA& scene, std::optional<double> field_cd_m2) {
      glare_ran = true;
      field_seen = field_cd_m2;
      return glare.apply(scene, GlareMode::static_eye, 0.0, nullptr, std::nullopt,
                         field_cd_m2.value_or(mean_luminance(scene)));
    };
    const PerceptionResult result = perception.process(lit, only(adaptation), period_s, period_s, 0.5, 0.5, field_glare);
    ASSERT_TRUE(glare_ran);
    if (!adaptation) {
      // No adaptation stage: the glare stage's own field luminance, the frame's mean.
      EXPECT_FALSE(field_seen.has_value());
      EXPECT_EQ(result.image.rgba, glare.apply(lit, GlareMode::static_eye, 0.0, nullptr, std::nullopt, mean_luminance(lit)).rgba);
      continue;
    }
    ASSERT_TRUE(field_seen.has_value());
    // One frame after the lamp came on, the eye is still near the dark (Eq. 5.2 with 1/60 s).
    TemporalAdaptation eye(frame_adaptation_luminance_cd_m2(dark, 0.5, 0.5), AdaptationTimeConstants{});
    eye.advance(frame_adaptation_luminance_cd_m2(dark, 0.5, 0.5), period_s);
    const double expected_cd_m2 = eye.advance(frame_adaptation_luminance_cd_m2(lit, 0.5, 0.5), period_s);
    EXPECT_NEAR(*field_seen, expected_cd_m2, 1e-12 * expected_cd_m2);
    EXPECT_DOUBLE_EQ(*field_seen, result.adapted_luminance_cd_m2);
    EXPECT_LT(*field_seen, 0.5 * mean_luminance(lit));
    EXPECT_GT(*field_seen, 10.0 * frame_adaptation_luminance_cd_m2(dark, 0.5, 0.5));
    // The frame is the glare of the eye adapted so (a larger pupil than the mean would give).
    const ImageRGBA adapted_glare = glare.apply(lit, GlareMode::static_eye, 0.0, nullptr, std::nullopt, *field_seen);
    const ImageRGBA mean_glare = glare.apply(lit, GlareMode::static_eye, 0.0, nullptr, std::nullopt, mean_luminance(lit));
    EXPECT_EQ(result.image.rgba, adapted_glare.rgba);
    EXPECT_NE(result.image.rgba, mean_glare.rgba);
  }
}

TEST(SessionPerception, TheEyeAdaptsExactlyForAnySplitOfTimeAndSeesTheBackgroundBetween) {
  DisplaySpec display = small_display();
  display.background_cd_m2 = 0.5;
  const ImageRGBA lit = lamp_frame(20.0f, 200.0f);
  const double y_cd_m2 = frame_adaptation_luminance_cd_m2(lit, 0.5, 0.5);
  // Per frame at 60 Hz against one step over the same time.
  SessionPerception per_frame(AdaptationTimeConstants{}, display), at_once(AdaptationTimeConstants{}, display);
  per_frame.see(1.0, 0.0, 0.1, 0, 1);
  at_once.see(1.0, 0.0, 0.1, 0, 1);
  for (int k = 0; k < 30; ++k) per_frame.process(lit, only(true), 0.5 + k / 60.0, 1.0 / 60.0, 0.5, 0.5);
  at_once.see(y_cd_m2, 0.5, 0.5, 0, 1);
  // Between 0.1 s and 0.5 s both saw the background.
  TemporalAdaptation eye(1.0, AdaptationTimeConstants{});
  eye.advance(1.0, 0.1);
  eye.advance(0.5, 0.4);
  const double expected_cd_m2 = eye.advance(y_cd_m2, 0.5);
  EXPECT_NEAR(*per_frame.adapted_luminance_cd_m2(), expected_cd_m2, 1e-9 * expected_cd_m2);
  EXPECT_NEAR(*at_once.adapted_luminance_cd_m2(), expected_cd_m2, 1e-9 * expected_cd_m2);
  // Frames without adaptation leave the image tone mapped for themselves but the eye still sees
  // them.
  SessionPerception instant(AdaptationTimeConstants{}, display);
  instant.see(0.001, 0.0, 1.0 / 60.0, 0, 1);
  instant.process(lit, only(false), 1.0 / 60.0, 0.25, 0.5, 0.5);
  TemporalAdaptation reference(0.001, AdaptationTimeConstants{});
  reference.advance(0.001, 1.0 / 60.0);
  EXPECT_NEAR(*instant.adapted_luminance_cd_m2(), reference.advance(y_cd_m2, 0.25), 1e-12);
}

}  // namespace
}  // namespace glarelab

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
    // One frame after the lamp came on, the eye is still near the dark (Eq. 5.2 with 1/60 s); it
    // came to the dark frame from the display's background.
    TemporalAdaptation eye(display.background_cd_m2, AdaptationTimeConstants{});
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
  // Both came to their first frame from the background, and saw it again between 0.1 s and 0.5 s.
  TemporalAdaptation eye(display.background_cd_m2, AdaptationTimeConstants{});
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
  TemporalAdaptation reference(display.background_cd_m2, AdaptationTimeConstants{});
  reference.advance(0.001, 1.0 / 60.0);
  EXPECT_NEAR(*instant.adapted_luminance_cd_m2(), reference.advance(y_cd_m2, 0.25), 1e-12);
}

// Issue 33: the eye met the session's first stimulus frame adapted to that frame, though the
// participant had been looking at the fixation background before it. It starts adapted to the
// display's background, holds there (a uniform field adapts to its own luminance) until the first
// frame, and adapts to the frame from there: Eq. 5.2's closed form, written out here,
//   L = Y + (B - Y) exp(-ft / tau(Y)),  tau(Y) = sigma tau_rod + (1 - sigma) tau_cone,
//   sigma = 0.04 / (0.04 + Y)  (Eqs. 5.3, 5.4; tau_rod 0.4 s, tau_cone 0.1 s).
TEST(SessionPerception, TheEyeMeetsTheFirstFrameAdaptedToTheBackgroundShownBeforeIt) {
  DisplaySpec display = small_display();
  display.background_cd_m2 = 2.0;
  const double y_cd_m2 = 20.0;
  const ImageRGBA uniform(96, 64, static_cast<float>(y_cd_m2));  // its adaptation luminance is Y at any gaze
  const double frame_time_s = 1.0 / 60.0;
  const auto closed_form = [](double start_cd_m2, double y, double elapsed_s) {
    const double sigma = 0.04 / (0.04 + y);
    const double tau_s = sigma * 0.4 + (1.0 - sigma) * 0.1;
    return y + (start_cd_m2 - y) * std::exp(-elapsed_s / tau_s);
  };
  for (const double first_flip_s : {0.0, 3.0}) {  // at once, or after 3 s of fixation background
    SessionPerception perception(AdaptationTimeConstants{}, display);
    EXPECT_FALSE(perception.adapted_luminance_cd_m2().has_value());  // no frame seen yet
    const PerceptionResult first = perception.process(uniform, only(true), first_flip_s, frame_time_s, 0.5, 0.5);
    const double expected_cd_m2 = closed_form(display.background_cd_m2, y_cd_m2, frame_time_s);
    EXPECT_NEAR(first.adapted_luminance_cd_m2, expected_cd_m2, 1e-6 * expected_cd_m2) << "first flip " << first_flip_s;
    // Far from the frame's own luminance, which the eye was taken to start at before.
    EXPECT_LT(first.adapted_luminance_cd_m2, 0.5 * y_cd_m2);
    // A second frame continues from there.
    const PerceptionResult second =
        perception.process(uniform, only(true), first_flip_s + frame_time_s, frame_time_s, 0.5, 0.5);
    EXPECT_NEAR(second.adapted_luminance_cd_m2, closed_form(display.background_cd_m2, y_cd_m2, 2 * frame_time_s),
                1e-6 * y_cd_m2);
  }
  // Frames passed by without stages (a preview before its trial) start from the background too.
  SessionPerception passed(AdaptationTimeConstants{}, display);
  passed.see(y_cd_m2, 1.0, frame_time_s, 0, 3);
  EXPECT_NEAR(*passed.adapted_luminance_cd_m2(), closed_form(display.background_cd_m2, y_cd_m2, 3 * frame_time_s),
              1e-9 * y_cd_m2);
}

}  // namespace
}  // namespace glarelab

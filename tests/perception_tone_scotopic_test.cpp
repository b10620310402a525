// Tone mapping (Narkowicz's fit of the ACES RRT + ODT, and the linear clip) and the scotopic colour
// shift (Luidolt 2020 Eq. 5.18; Spencer et al. 1995 section 5).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "stimuli/perception/scotopic_colour.h"
#include "stimuli/perception/tone_mapping.h"

namespace glarelab {
namespace {

TEST(PerceptionToneMapping, AcesCurveMatchesThePublishedFormula) {
  // Narkowicz 2016: f(x) = x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), clamped to [0, 1].
  EXPECT_EQ(aces_narkowicz_curve(0.0), 0.0);
  // f(1) = 2.54 / 3.16 = 0.8038 ("1 on input maps to ~0.8 on output").
  EXPECT_NEAR(aces_narkowicz_curve(1.0), 2.54 / 3.16, 1e-15);
  EXPECT_NEAR(aces_narkowicz_curve(1.0), 0.8, 0.005);
  // f(0.18) = 0.18 * 0.4818 / (0.18 * 1.0274 + 0.14) = 0.086724 / 0.324932.
  EXPECT_NEAR(aces_narkowicz_curve(0.18), 0.086724 / 0.324932, 1e-12);
  // f(0.5) = 0.5 * 1.285 / (0.5 * 1.805 + 0.14) = 0.6425 / 1.0425.
  EXPECT_NEAR(aces_narkowicz_curve(0.5), 0.6425 / 1.0425, 1e-12);
  // f(10) = 251.3 / 249.04 > 1: clamped (the curve overshoots 1 above x = 7.24 on its way to 2.51/2.43).
  EXPECT_EQ(aces_narkowicz_curve(10.0), 1.0);
}

TEST(PerceptionToneMapping, HillFitMatchesThePublishedFormula) {
  // Hill's RRTAndODTFit(v) = (v (v + 0.0245786) - 0.000090537) / (v (0.983729 v + 0.4329510) + 0.238081).
  EXPECT_NEAR(aces_hill_rrt_odt_fit(0.18), (0.18 * 0.2045786 - 0.000090537) / (0.18 * (0.983729 * 0.18 + 0.4329510) + 0.238081),
              1e-15);
  EXPECT_NEAR(aces_hill_rrt_odt_fit(0.18), 0.10559, 1e-5);  // ACES: 18 % grey near 10 % of the display
  // A grey stays grey (both matrices' rows sum to 1 within 1e-5).
  const double grey[3] = {0.5, 0.5, 0.5};
  double out[3];
  aces_hill_transform(grey, out);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[c], aces_hill_rrt_odt_fit(0.5), 2e-5) << c;
  // A colour, by hand: (0.8, 0.2, 0.05) through ACESInputMat is (0.5510795, 0.243251, 0.0913745); the fit
  // gives (0.4089956, 0.1619982, 0.0367481); ACESOutputMat gives (0.5675945, 0.1375424, 0.0264172).
  const double colour[3] = {0.8, 0.2, 0.05};
  aces_hill_transform(colour, out);
  EXPECT_NEAR(out[0], 0.5675945, 1e-6);
  EXPECT_NEAR(out[1], 0.1375424, 1e-6);
  EXPECT_NEAR(out[2], 0.0264172, 1e-6);
  // Key rule without Narkowicz's 0.6: the adapted luminance goes in as 0.18.
  ToneMappingSettings hill;
  hill.curve = ToneCurve::aces_hill;
  EXPECT_NEAR(tone_map_channel_cd_m2(2.0, 2.0, hill, 100.0), 100.0 * 0.10559124722893, 2e-3);
  // Black stays black (the fit's -0.000090537 is clamped away).
  EXPECT_EQ(tone_map_channel_cd_m2(0.0, 2.0, hill, 100.0), 0.0);
}

TEST(PerceptionToneMapping, MonotonicInSceneLuminance) {
  for (ToneCurve curve : {ToneCurve::aces_narkowicz, ToneCurve::aces_hill}) {
    ToneMappingSettings settings;
    settings.curve = curve;
    double previous = -1.0;
    for (double log_cd = -4.0; log_cd <= 6.0; log_cd += 0.01) {
      const double out = tone_map_channel_cd_m2(std::pow(10.0, log_cd), 1.0, settings, 250.0);
      ASSERT_GE(out, previous) << log_cd;
      ASSERT_GE(out, 0.0);
      ASSERT_LE(out, 250.0);
      previous = out;
    }
  }
  double previous_x = -1.0;
  for (double x = 0.0; x <= 50.0; x += 1e-3) {
    const double y = aces_narkowicz_curve(x);
    ASSERT_GE(y, previous_x) << x;
    previous_x = y;
  }
}

TEST(PerceptionToneMapping, AdaptedLuminanceMapsToMiddleGrey) {
  // Key rule: a pixel at the adapted luminance goes in as 0.6 * 0.18 and comes out at peak * f(0.108),
  // whatever the adaptation level.
  const ToneMappingSettings settings;
  const double expected = 250.0 * (0.108 * (2.51 * 0.108 + 0.03)) / (0.108 * (2.43 * 0.108 + 0.59) + 0.14);
  for (double adapted : {0.01, 1.0, 1000.0})
    EXPECT_NEAR(tone_map_channel_cd_m2(adapted, adapted, settings, 250.0), expected, 1e-12) << adapted;
  // Below the floor (1e-6 cd/m2) the exposure stops growing.
  EXPECT_EQ(tone_mapping_exposure_per_cd_m2(0.0, settings), 0.6 * 0.18 / 1e-6);
}

TEST(PerceptionToneMapping, NoneIsTheClipAtThePeak) {
  ToneMappingSettings settings;
  settings.curve = ToneCurve::none;
  ImageRGBA frame(5, 1, 0.0f);
  const float values[5] = {-1.0f, 0.0f, 50.0f, 250.0f, 1e5f};
  for (int x = 0; x < 5; ++x) {
    float* p = frame.pixel(x, 0);
    p[0] = values[x];
    p[1] = values[x] * 0.5f;
    p[2] = values[x] * 2.0f;
    p[3] = 0.25f;
  }
  const ImageRGBA out = tone_map(frame, 3.0, settings, 250.0);
  for (int x = 0; x < 5; ++x)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(out.pixel(x, 0)[c], std::clamp(frame.pixel(x, 0)[c], 0.0f, 250.0f)) << x << "," << c;
  EXPECT_EQ(out.pixel(2, 0)[3], 0.25f);
}

TEST(PerceptionToneMapping, RefusesBadSettingsNamingTheField) {
  ToneMappingSettings settings;
  settings.middle_grey = 2.0;
  try {
    validate_tone_mapping_settings(settings);
    FAIL() << "middle_grey = 2 was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("middle_grey must be in (0, 1]"), std::string::npos) << error.what();
  }
}

double rod_sensitivity_by_hand(double adapted_cd_m2) { return 0.04 / (0.04 + adapted_cd_m2); }

ImageRGBA one_pixel(double r, double g, double b) {
  ImageRGBA image(1, 1, 0.0f);
  float* p = image.pixel(0, 0);
  p[0] = static_cast<float>(r);
  p[1] = static_cast<float>(g);
  p[2] = static_cast<float>(b);
  p[3] = 1.0f;
  return image;
}

TEST(PerceptionScotopic, DaylightLeavesTheColourAlone) {
  const ImageRGBA in = one_pixel(100.0, 50.0, 20.0);
  const ImageRGBA out = apply_scotopic_colour(in, rod_sensitivity_by_hand(1e6), ScotopicSettings{});
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(out.pixel(0, 0)[c], in.pixel(0, 0)[c], 1e-6 * in.pixel(0, 0)[c]);
}

TEST(PerceptionScotopic, Eq518HandComputed) {
  // (100, 50, 20): L' = 0.2125 * 100 + 0.7154 * 50 + 0.0721 * 20 = 58.462.
  const double luminance = 58.462;
  // At L_i = 0.04 cd/m2 the rods are half sensitive: SV = RGB / 2 + tint L' / 2.
  const ImageRGBA half = apply_scotopic_colour(one_pixel(100.0, 50.0, 20.0), rod_sensitivity_by_hand(0.04), {});
  EXPECT_NEAR(half.pixel(0, 0)[0], 50.0 + 0.5 * 1.05 * luminance, 1e-4);
  EXPECT_NEAR(half.pixel(0, 0)[1], 25.0 + 0.5 * 0.97 * luminance, 1e-4);
  EXPECT_NEAR(half.pixel(0, 0)[2], 10.0 + 0.5 * 1.27 * luminance, 1e-4);
  // Full rod sensitivity (L_i = 0): the tint times the pixel's luminance.
  const ImageRGBA dark = apply_scotopic_colour(one_pixel(100.0, 50.0, 20.0), rod_sensitivity_by_hand(0.0), {});
  EXPECT_NEAR(dark.pixel(0, 0)[0], 1.05 * luminance, 1e-4);
  EXPECT_NEAR(dark.pixel(0, 0)[1], 0.97 * luminance, 1e-4);
  EXPECT_NEAR(dark.pixel(0, 0)[2], 1.27 * luminance, 1e-4);
  // And it tends there: at L_i = 1e-6 cd/m2, 1 - sigma = 1e-6 / 0.040001 = 2.5e-5 of the way from
  // the tint to the colour remains.
  const ImageRGBA near_dark = apply_scotopic_colour(one_pixel(100.0, 50.0, 20.0), rod_sensitivity_by_hand(1e-6), {});
  const double remaining = 1e-6 / 0.040001;
  EXPECT_NEAR(near_dark.pixel(0, 0)[2], 1.27 * luminance + remaining * (20.0 - 1.27 * luminance), 1e-4);
  EXPECT_LT(std::abs(near_dark.pixel(0, 0)[2] - 1.27 * luminance), 2e-3);
}

// HSV from RGB by the textbook formulas (hue in degrees), independent of the code under test.
struct Hsv {
  double h, s, v;
};
Hsv to_hsv(double r, double g, double b) {
  const double v = std::max({r, g, b}), lo = std::min({r, g, b}), d = v - lo;
  double h = 0.0;
  if (d > 0.0) {
    if (v == r) h = 60.0 * std::fmod((g - b) / d, 6.0);
    else if (v == g) h = 60.0 * ((b - r) / d + 2.0);
    else h = 60.0 * ((r - g) / d + 4.0);
  }
  return {h, v > 0.0 ? d / v : 0.0, v};
}

TEST(PerceptionScotopic, SpencerDesaturatesBySeventyPercentInFullRodVision) {
  ScotopicSettings settings;
  settings.form = ScotopicForm::spencer_desaturation;
  // (80, 40, 20): V = 80, S = 0.75, H = 60 * (40 - 20) / 60 = 20 degrees. S' = 0.3 * 0.75 = 0.225:
  // every channel moves to 80 - (80 - c) * 0.3: (80, 68, 62), by hand.
  const ImageRGBA out = apply_scotopic_colour(one_pixel(80.0, 40.0, 20.0), 1.0, settings);
  const float* p = out.pixel(0, 0);
  EXPECT_NEAR(p[0], 80.0, 1e-5);
  EXPECT_NEAR(p[1], 68.0, 1e-5);
  EXPECT_NEAR(p[2], 62.0, 1e-5);
  const Hsv before = to_hsv(80.0, 40.0, 20.0), after = to_hsv(p[0], p[1], p[2]);
  EXPECT_NEAR(before.s, 0.75, 1e-12);
  EXPECT_NEAR(after.s, 0.3 * before.s, 1e-6);
  EXPECT_NEAR(after.h, before.h, 1e-4);
  EXPECT_NEAR(after.h, 20.0, 1e-4);
  EXPECT_NEAR(after.v, before.v, 1e-6);
  // Half rod sensitivity: 35 % reduction; daylight: none.
  const ImageRGBA half = apply_scotopic_colour(one_pixel(80.0, 40.0, 20.0), 0.5, settings);
  EXPECT_NEAR(to_hsv(half.pixel(0, 0)[0], half.pixel(0, 0)[1], half.pixel(0, 0)[2]).s, 0.65 * 0.75, 1e-6);
  const ImageRGBA day = apply_scotopic_colour(one_pixel(80.0, 40.0, 20.0), 0.0, settings);
  EXPECT_EQ(day.pixel(0, 0)[1], 40.0f);
}

TEST(PerceptionScotopic, RefusesBadValues) {
  ScotopicSettings settings;
  settings.spencer_saturation_reduction = 1.5;
  EXPECT_THROW(apply_scotopic_colour(one_pixel(1, 1, 1), 0.5, settings), std::invalid_argument);
  EXPECT_THROW(apply_scotopic_colour(one_pixel(1, 1, 1), 1.5, ScotopicSettings{}), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab

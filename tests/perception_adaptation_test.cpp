// Luidolt 2020 section 5.1: the frame's adaptation luminance (gaze-weighted, 128 x 128, pyramid to
// 16 x 16, Eq. 5.1) and the temporal filter of Eqs. 5.2-5.4.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "stimuli/perception/frame_adaptation_luminance.h"
#include "stimuli/perception/temporal_adaptation.h"

namespace glarelab {
namespace {

// Eqs. 5.3 and 5.4 written out by hand: sigma(Y) = 0.04 / (0.04 + Y), tau = sigma 0.4 + (1 - sigma) 0.1.
double hand_tau_s(double luminance_cd_m2) {
  const double sigma = 0.04 / (0.04 + luminance_cd_m2);
  return sigma * 0.4 + (1.0 - sigma) * 0.1;
}

TEST(PerceptionAdaptation, StepFollowsClosedFormAtAnyRefreshRate) {
  // A step from 1 to 1000 cd/m2 at t = 0: L(t) = 1000 + (1 - 1000) exp(-t / tau(1000)).
  const double tau_up_s = hand_tau_s(1000.0);
  for (double refresh_hz : {60.0, 90.0, 144.0}) {
    TemporalAdaptation eye(1.0);
    const double dt = 1.0 / refresh_hz;
    double worst_relative = 0.0;
    const int frames = static_cast<int>(2.0 * refresh_hz);
    for (int n = 1; n <= frames; ++n) {
      const double adapted = eye.advance(1000.0, dt);
      const double closed_form = 1000.0 + (1.0 - 1000.0) * std::exp(-n * dt / tau_up_s);
      worst_relative = std::max(worst_relative, std::abs(adapted - closed_form) / closed_form);
      ASSERT_NEAR(adapted, closed_form, 1e-12 * closed_form) << refresh_hz << " Hz, frame " << n;
    }
    std::printf("step 1 -> 1000 cd/m2 at %.0f Hz: L(2 s) = %.12f cd/m2, worst relative error %.2e\n", refresh_hz,
                eye.adapted_luminance_cd_m2(), worst_relative);
  }
  // The same instant (1/3 s) reached at the three rates gives the same adapted luminance.
  double at_third[3];
  int k = 0;
  for (double refresh_hz : {60.0, 90.0, 144.0}) {
    TemporalAdaptation eye(1.0);
    const int frames = static_cast<int>(std::lround(refresh_hz / 3.0));
    for (int n = 0; n < frames; ++n) eye.advance(1000.0, 1.0 / refresh_hz);
    at_third[k++] = eye.adapted_luminance_cd_m2();
  }
  const double closed_form = 1000.0 - 999.0 * std::exp(-(1.0 / 3.0) / tau_up_s);
  for (double value : at_third) EXPECT_NEAR(value, closed_form, 1e-12 * closed_form);
}

TEST(PerceptionAdaptation, DownStepUsesTheDarkTimeConstant) {
  // 1000 -> 1 cd/m2: tau(1) = (0.04 / 1.04) 0.4 + (1 / 1.04) 0.1 = 0.111538... s, slower than tau(1000).
  TemporalAdaptation eye(1000.0);
  const double tau_down_s = hand_tau_s(1.0);
  EXPECT_NEAR(tau_down_s, (0.04 * 0.4 + 1.0 * 0.1) / 1.04, 1e-15);
  for (int n = 1; n <= 90; ++n) {
    const double adapted = eye.advance(1.0, 1.0 / 90.0);
    const double closed_form = 1.0 + 999.0 * std::exp(-(n / 90.0) / tau_down_s);
    ASSERT_NEAR(adapted, closed_form, 1e-12 * closed_form) << "frame " << n;
  }
  // In full darkness sigma -> 1 and tau -> tau_rod = 0.4 s: after 0.4 s, 1/e of the way remains.
  TemporalAdaptation dark(1.0);
  dark.advance(0.0, 0.4);
  EXPECT_NEAR(dark.adapted_luminance_cd_m2(), std::exp(-1.0), 1e-15);
  EXPECT_NEAR(dark.rod_sensitivity(), 0.04 / (0.04 + std::exp(-1.0)), 1e-15);
}

TEST(PerceptionAdaptation, IrregularFrameTimesComposeExactly) {
  // Two frames of 7 ms and 4 ms at the same luminance equal one frame of 11 ms.
  TemporalAdaptation split(3.0), whole(3.0);
  split.advance(250.0, 0.007);
  split.advance(250.0, 0.004);
  whole.advance(250.0, 0.011);
  EXPECT_NEAR(split.adapted_luminance_cd_m2(), whole.adapted_luminance_cd_m2(), 1e-13);
}

TEST(PerceptionAdaptation, RefusesNegativeOrNonFiniteInput) {
  TemporalAdaptation eye(1.0);
  EXPECT_THROW(eye.advance(-1.0, 0.01), std::invalid_argument);
  EXPECT_THROW(eye.advance(1.0, -0.01), std::invalid_argument);
  EXPECT_THROW(eye.advance(NAN, 0.01), std::invalid_argument);
  AdaptationTimeConstants bad;
  bad.rod_time_constant_s = 0.0;
  try {
    TemporalAdaptation refused(1.0, bad);
    FAIL() << "a zero rod time constant was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("rod_time_constant_s"), std::string::npos) << error.what();
  }
}

ImageRGBA uniform_frame(int width, int height, float cd_m2) {
  ImageRGBA frame(width, height, 0.0f);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float* p = frame.pixel(x, y);
      p[0] = p[1] = p[2] = cd_m2;
      p[3] = 1.0f;
    }
  return frame;
}

void add_square(ImageRGBA& frame, int cx, int cy, int side, float cd_m2) {
  for (int y = cy - side / 2; y < cy + side / 2; ++y)
    for (int x = cx - side / 2; x < cx + side / 2; ++x) {
      float* p = frame.pixel(x, y);
      p[0] = p[1] = p[2] = cd_m2;
    }
}

TEST(PerceptionAdaptation, UniformFieldAdaptsToItsLuminanceWithEq51Weights) {
  const ImageRGBA grey = uniform_frame(320, 180, 10.0f);
  EXPECT_NEAR(frame_adaptation_luminance_cd_m2(grey, 0.3, 0.7), 10.0 * (0.2125 + 0.7154 + 0.0721), 1e-12);
  // A coloured field: Eq. 5.1's weights, Y = 0.2125 R + 0.7154 G + 0.0721 B.
  ImageRGBA colour(200, 150, 0.0f);
  for (int y = 0; y < 150; ++y)
    for (int x = 0; x < 200; ++x) {
      float* p = colour.pixel(x, y);
      p[0] = 4.0f;
      p[1] = 2.0f;
      p[2] = 8.0f;
    }
  EXPECT_NEAR(frame_adaptation_luminance_cd_m2(colour, 0.5, 0.5), 0.2125 * 4 + 0.7154 * 2 + 0.0721 * 8, 1e-12);
}

TEST(PerceptionAdaptation, PeripheralSourceCountsLessThanOneAtTheGaze) {
  const int width = 320, height = 180;
  const ImageRGBA background = uniform_frame(width, height, 1.0f);
  const double base = frame_adaptation_luminance_cd_m2(background, 0.5, 0.5);
  ImageRGBA at_gaze = background, far = background;
  add_square(at_gaze, width / 2, height / 2, 4, 10000.0f);
  add_square(far, 32, 18, 4, 10000.0f);  // centred on (0.1, 0.1) of the frame
  const double rise_at_gaze = frame_adaptation_luminance_cd_m2(at_gaze, 0.5, 0.5) - base;
  const double rise_far = frame_adaptation_luminance_cd_m2(far, 0.5, 0.5) - base;
  // The Gaussian weights by hand (sigma = 0.125 frame widths): the far source is 0.4 widths across and
  // 0.4 x 180 / 320 = 0.225 widths down from the gaze: exp(-(0.16 + 0.050625) / (2 0.015625)).
  const double weight_ratio = std::exp(-(0.16 + 0.050625) / (2.0 * 0.125 * 0.125));
  std::printf("adaptation luminance rise from a 4 x 4 px, 1e4 cd/m2 source: at the gaze %.4f cd/m2, at (0.1, 0.1) "
              "%.6f cd/m2; ratio %.5f, Gaussian weight ratio %.5f\n",
              rise_at_gaze, rise_far, rise_far / rise_at_gaze, weight_ratio);
  EXPECT_GT(rise_at_gaze, 0.0);
  EXPECT_LT(rise_far, 0.01 * rise_at_gaze);
  // The resampling and pyramid are averages: they carry the weighted light through, so the ratio is
  // the Gaussian's within the edge clamping of the pyramid.
  EXPECT_NEAR(rise_far / rise_at_gaze, weight_ratio, 0.25 * weight_ratio);
}

TEST(PerceptionAdaptation, RefusesBadWeighting) {
  const ImageRGBA grey = uniform_frame(64, 64, 1.0f);
  AdaptationWeighting bad;
  bad.gaze_sigma_frame_widths = 0.0;
  EXPECT_THROW(frame_adaptation_luminance_cd_m2(grey, 0.5, 0.5, bad), std::invalid_argument);
  EXPECT_THROW(frame_adaptation_luminance_cd_m2(grey, NAN, 0.5), std::invalid_argument);
  EXPECT_THROW(frame_adaptation_luminance_cd_m2(ImageRGBA(), 0.5, 0.5), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab

// [glare] gaze_window_px for every glare model (stimuli/glare_stage.h, docs/GLARE_OPTICS.md 7a):
// a frame glared with a gaze window is, inside the window, the unwindowed frame's glare blended in
// by Luidolt's Gaussian falloff, w = exp(-d^2 / (2 sigma^2)) with sigma = side / 6 (written out
// here), and outside it the frame itself, bit for bit. The wave-optics models (ritschel, luidolt)
// convolve the window with the PSF's reach as apron, so their window equals the full convolution to
// FFT rounding; the analytic, hybrid and human kernels reach every pixel, so the window takes the
// frame's glare.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "glare/analytic/analytic_psf.h"
#include "stimuli/glare_stage.h"

namespace glarelab {
namespace {

constexpr int kWidth = 96, kHeight = 64, kWindowPx = 32;
constexpr float kLampCdM2 = 5000.0f;

DisplaySpec small_display() {
  DisplaySpec display;
  display.width_px = kWidth;
  display.height_px = kHeight;
  display.peak_luminance_cd_m2 = 200.0;
  return display;
}

GlareSpec spec_for(GlareModel model, int window_px) {
  GlareSpec spec;
  spec.model = model;
  spec.backend = GlareBackendRequest::cpu;
  spec.grid_px = 128;
  spec.wavelength_samples = 8;
  spec.spencer_regime = SpencerRegime::mesopic;
  spec.observer_eye = ObserverEye{45.0, 0.7};
  spec.gaze_window_px = window_px;
  return spec;
}

ImageRGBA lamp_frame() {
  ImageRGBA frame(kWidth, kHeight, 1.0f);
  for (int y = 22; y < 26; ++y)
    for (int x = 30; x < 34; ++x)
      for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = kLampCdM2;
  return frame;
}

TEST(GlareStageGazeWindow, EveryModelConfinesItsGlareToTheWindow) {
  const ImageRGBA frame = lamp_frame();
  const GazePoint gaze{0.35, 0.4};  // pixel (33.6, 25.6): the window spans x 18-49, y 10-41
  const double gaze_x = gaze.x * kWidth, gaze_y = gaze.y * kHeight, sigma = kWindowPx / 6.0;
  const int x0 = static_cast<int>(std::lround(gaze_x - kWindowPx / 2.0)), y0 = static_cast<int>(std::lround(gaze_y - kWindowPx / 2.0));
  for (const GlareModel model : {GlareModel::human, GlareModel::hybrid, GlareModel::spencer, GlareModel::cie,
                                 GlareModel::ritschel, GlareModel::luidolt}) {
    GlareStage whole(spec_for(model, 0), small_display(), 3);
    GlareStage windowed(spec_for(model, kWindowPx), small_display(), 3);
    GlareFrameReport whole_report, window_report;
    const ImageRGBA full = whole.apply(frame, GlareMode::static_eye, 0.0, &whole_report, gaze);
    const ImageRGBA out = windowed.apply(frame, GlareMode::static_eye, 0.0, &window_report, gaze);
    ASSERT_TRUE(window_report.convolved) << to_string(model);
    ASSERT_TRUE(window_report.window.has_value()) << to_string(model);
    EXPECT_EQ(window_report.window->x0_px, x0) << to_string(model);
    EXPECT_EQ(window_report.window->y0_px, y0) << to_string(model);
    double worst_inside = 0.0, glare_inside = 0.0;
    int changed_outside = 0;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        const bool inside = x >= x0 && x < x0 + kWindowPx && y >= y0 && y < y0 + kWindowPx;
        const double d2 = std::pow(x + 0.5 - gaze_x, 2) + std::pow(y + 0.5 - gaze_y, 2);
        const double w = inside ? std::exp(-d2 / (2.0 * sigma * sigma)) : 0.0;
        for (int c = 0; c < 3; ++c) {
          const double base = frame.pixel(x, y)[c];
          const double expected = base + w * (static_cast<double>(full.pixel(x, y)[c]) - base);
          if (!inside) {
            changed_outside += out.pixel(x, y)[c] != frame.pixel(x, y)[c] ? 1 : 0;
            continue;
          }
          worst_inside = std::max(worst_inside, std::abs(out.pixel(x, y)[c] - expected));
          glare_inside = std::max(glare_inside, w * std::abs(static_cast<double>(full.pixel(x, y)[c]) - base));
        }
      }
    std::printf("%s: largest difference inside the window %.3g cd/m2 (glare there up to %.3g)\n", to_string(model).c_str(),
                worst_inside, glare_inside);
    EXPECT_EQ(changed_outside, 0) << to_string(model);
    // Float frames; the wave-optics window is a second FFT of the cropped frame (rounding of 1e-6
    // of the lamp, which its pixels hold).
    EXPECT_LT(worst_inside, 2e-6 * kLampCdM2) << to_string(model);
    EXPECT_GT(glare_inside, 0.01) << to_string(model);
  }
}

}  // namespace
}  // namespace glarelab

// Gaze-contingent glare window (Luidolt 2020, 5.2.3): the windowed convolution against the
// full-frame convolution (glare/cpu/convolution.h) inside the window, the Gaussian blend weights
// against the formula, and windows clamped at the image corners.
#include <gtest/gtest.h>

#include <cmath>

#include "glare/cpu/gaze_window_convolution.h"
#include "core/random.h"

namespace glarelab {
namespace {

constexpr int kWidth = 96;
constexpr int kHeight = 80;

// A positive, unevenly shaped 33 x 33 PSF (reach 16 px) summing to 1: a core plus a slow tail, so
// sources up to the PSF's edge matter.
Psf test_psf() {
  Psf psf;
  psf.size_px = 33;
  psf.degrees_per_pixel = 0.01;
  psf.values.resize(33 * 33);
  double sum = 0.0;
  for (int y = 0; y < 33; ++y)
    for (int x = 0; x < 33; ++x) {
      const double r2 = (x - 16.0) * (x - 16.0) + 1.7 * (y - 16.0) * (y - 16.0) + 0.3 * (x - 16.0);
      psf.at(0, x, y) = std::exp(-std::max(r2, 0.0) / 4.0) + 0.02 / (1.0 + 0.1 * std::abs(r2));
      sum += psf.at(0, x, y);
    }
  for (double& v : psf.values) v /= sum;
  return psf;
}

// Background 0.05..1.05 with a few 1e4 sources, one near every edge.
std::vector<double> test_plane() {
  const CounterRandom random(3, RandomStream::observer);
  std::vector<double> plane(static_cast<std::size_t>(kWidth) * kHeight);
  for (std::size_t k = 0; k < plane.size(); ++k) plane[k] = 0.05 + random.uniform(k);
  for (const auto& [x, y] : {std::pair{2, 40}, std::pair{90, 5}, std::pair{50, 78}, std::pair{48, 40}})
    plane[static_cast<std::size_t>(y) * kWidth + x] = 1e4;
  return plane;
}

// Largest |windowed - full| / full over window pixels at least `margin` px inside the window border.
double max_relative_error(const std::vector<double>& windowed, const std::vector<double>& full, const GazeWindow& w,
                          int margin) {
  double worst = 0.0;
  for (int y = margin; y < w.height_px - margin; ++y)
    for (int x = margin; x < w.width_px - margin; ++x) {
      const double reference = full[static_cast<std::size_t>(w.y0_px + y) * kWidth + (w.x0_px + x)];
      const double value = windowed[static_cast<std::size_t>(y) * w.width_px + x];
      worst = std::max(worst, std::abs(value - reference) / reference);
    }
  return worst;
}

TEST(GlareGazeWindow, WindowEqualsTheFullConvolutionWithTheDefaultApron) {
  const Psf psf = test_psf();
  const auto plane = test_plane();
  const auto full = convolve_plane_cpu(plane, kWidth, kHeight, psf, 0, {});
  GazeWindowOptions options;
  options.window_px = 32;
  for (const auto& [gx, gy] : {std::pair{0.5, 0.5}, std::pair{0.3, 0.7}, std::pair{0.0, 0.0}, std::pair{1.0, 1.0},
                               std::pair{1.0, 0.0}}) {
    const GazeWindow window = place_gaze_window(kWidth, kHeight, gx, gy, psf.size_px, options);
    EXPECT_EQ(window.apron_px, 16);
    const auto windowed = convolve_gaze_window_plane(plane, kWidth, kHeight, psf, 0, window, {});
    EXPECT_LT(max_relative_error(windowed, full, window, 0), 1e-9) << "gaze " << gx << ", " << gy;
  }
}

TEST(GlareGazeWindow, ShortApronIsExactOnlyBeyondTheMissingReach) {
  const Psf psf = test_psf();
  const auto plane = test_plane();
  const auto full = convolve_plane_cpu(plane, kWidth, kHeight, psf, 0, {});
  GazeWindowOptions options;
  options.window_px = 64;
  options.apron_px = 4;  // 12 px short of the PSF's reach of 16
  // Centred gaze: the 64 x 64 window lies at (16, 8), its apron inside the 96 x 80 image, and the
  // 1e4 source at (2, 40) is 14 px left of it: the full convolution sees it, the window does not.
  const GazeWindow window = place_gaze_window(kWidth, kHeight, 0.5, 0.5, psf.size_px, options);
  ASSERT_EQ(window.x0_px, 16);
  ASSERT_EQ(window.y0_px, 8);
  const auto windowed = convolve_gaze_window_plane(plane, kWidth, kHeight, psf, 0, window, {});
  EXPECT_LT(max_relative_error(windowed, full, window, 16 - 4), 1e-9);
  EXPECT_GT(max_relative_error(windowed, full, window, 0), 1e-3);  // the margin is needed
}

TEST(GlareGazeWindow, BlendWeightIsTheStatedGaussianAroundTheGaze) {
  GazeWindowOptions options;
  options.window_px = 32;
  // Gaze on the centre of pixel (40, 30): x = 40.5 / 96, y = 30.5 / 80.
  const GazeWindow window = place_gaze_window(kWidth, kHeight, 40.5 / kWidth, 30.5 / kHeight, 33, options);
  EXPECT_DOUBLE_EQ(window.sigma_px, 32.0 / 6.0);
  EXPECT_DOUBLE_EQ(gaze_blend_weight(window, 40, 30), 1.0);
  const double sigma = 32.0 / 6.0;
  for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{5, 0}, std::pair{0, -7}, std::pair{-10, 12}}) {
    const double d2 = dx * dx + dy * dy;
    EXPECT_NEAR(gaze_blend_weight(window, 40 + dx, 30 + dy), std::exp(-d2 / (2 * sigma * sigma)), 1e-15);
  }
  EXPECT_EQ(gaze_blend_weight(window, window.x0_px - 1, 30), 0.0);  // outside the window
  EXPECT_EQ(gaze_blend_weight(window, window.x0_px + window.width_px, 30), 0.0);
  options.falloff_sigma_px = 3.0;
  const GazeWindow narrow = place_gaze_window(kWidth, kHeight, 40.5 / kWidth, 30.5 / kHeight, 33, options);
  EXPECT_NEAR(gaze_blend_weight(narrow, 43, 30), std::exp(-0.5), 1e-15);  // one sigma away
}

TEST(GlareGazeWindow, BlendKeepsTheBaseOutsideAndTheGlareAtTheGaze) {
  const Psf psf = test_psf();
  const auto plane = test_plane();
  const auto full = convolve_plane_cpu(plane, kWidth, kHeight, psf, 0, {});
  GazeWindowOptions options;
  options.window_px = 32;
  const GazeWindow window = place_gaze_window(kWidth, kHeight, 40.5 / kWidth, 30.5 / kHeight, psf.size_px, options);
  const auto windowed = convolve_gaze_window_plane(plane, kWidth, kHeight, psf, 0, window, {});
  const auto blended = blend_gaze_window_plane(plane, kWidth, kHeight, windowed, window);
  const auto at = [](const std::vector<double>& p, int x, int y) { return p[static_cast<std::size_t>(y) * kWidth + x]; };
  EXPECT_NEAR(at(blended, 40, 30), at(full, 40, 30), 1e-9 * at(full, 40, 30));
  const double w = gaze_blend_weight(window, 45, 33);
  EXPECT_NEAR(at(blended, 45, 33), at(plane, 45, 33) + w * (at(full, 45, 33) - at(plane, 45, 33)), 1e-9);
  EXPECT_EQ(at(blended, 90, 70), at(plane, 90, 70));  // outside the window: the base, untouched
  EXPECT_EQ(at(blended, 0, 0), at(plane, 0, 0));
}

TEST(GlareGazeWindow, CornerGazeClampsTheWindowButNotTheFalloff) {
  GazeWindowOptions options;
  options.window_px = 32;
  const GazeWindow top_left = place_gaze_window(kWidth, kHeight, 0.0, 0.0, 33, options);
  EXPECT_EQ(top_left.x0_px, 0);
  EXPECT_EQ(top_left.y0_px, 0);
  const double sigma = 32.0 / 6.0;
  EXPECT_NEAR(gaze_blend_weight(top_left, 0, 0), std::exp(-0.5 / (2 * sigma * sigma)), 1e-15);
  const GazeWindow bottom_right = place_gaze_window(kWidth, kHeight, 1.0, 1.0, 33, options);
  EXPECT_EQ(bottom_right.x0_px, kWidth - 32);
  EXPECT_EQ(bottom_right.y0_px, kHeight - 32);
  const GazeWindow off_display = place_gaze_window(kWidth, kHeight, 1.3, -0.2, 33, options);
  EXPECT_EQ(off_display.x0_px, kWidth - 32);
  EXPECT_EQ(off_display.y0_px, 0);
  // A window larger than the image covers it.
  options.window_px = 128;
  const GazeWindow whole = place_gaze_window(kWidth, kHeight, 0.2, 0.9, 33, options);
  EXPECT_EQ(whole.x0_px, 0);
  EXPECT_EQ(whole.width_px, kWidth);
  EXPECT_EQ(whole.height_px, kHeight);
}

TEST(GlareGazeWindow, RefusesWindowsThatAreNotPowersOfTwo) {
  GazeWindowOptions options;
  options.window_px = 300;
  EXPECT_THROW(place_gaze_window(kWidth, kHeight, 0.5, 0.5, 33, options), std::invalid_argument);
  options.window_px = 256;
  EXPECT_THROW(place_gaze_window(kWidth, kHeight, NAN, 0.5, 33, options), std::invalid_argument);
}

TEST(GlareGazeWindow, ImagePathBlendsEachChannelIntoTheUnconvolvedImage) {
  const Psf psf = test_psf();
  ImageRGBA image(kWidth, kHeight, 0.0f);
  const auto plane = test_plane();
  for (std::size_t k = 0; k < plane.size(); ++k) {
    image.rgba[4 * k] = static_cast<float>(plane[k]);
    image.rgba[4 * k + 1] = static_cast<float>(0.5 * plane[k]);
    image.rgba[4 * k + 2] = 0.25f;
    image.rgba[4 * k + 3] = 1.0f;
  }
  GazeWindowOptions options;
  options.window_px = 32;
  const ImageRGBA full = convolve_image_cpu(image, psf, {});
  const ImageRGBA gazed = convolve_image_gaze_window_cpu(image, psf, 40.5 / kWidth, 30.5 / kHeight, options);
  for (int c = 0; c < 4; ++c) {
    EXPECT_NEAR(gazed.pixel(40, 30)[c], full.pixel(40, 30)[c], 1e-6 * std::abs(full.pixel(40, 30)[c])) << c;
    EXPECT_EQ(gazed.pixel(90, 70)[c], image.pixel(90, 70)[c]) << c;
  }
}

}  // namespace
}  // namespace glarelab

// Luidolt 2020 section 5.3: acuity loss in the dark (Eqs. 5.14-5.17), separable against 2D.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "stimuli/perception/acuity_loss.h"
#include "stimuli/perception/lab_colour.h"

namespace glarelab {
namespace {

constexpr double kPi = 3.14159265358979323846;
// The thesis' headset: 1440 px across 104 degrees (section 5.3.2).
constexpr double kThesisPixelsPerDegree = 1440.0 / 104.0;

TEST(PerceptionAcuity, ResolvableFrequencyMatchesTheThesis) {
  // Section 5.3.2 and Fig. 2.9 (Larson et al. 1997): 47.5 and 5.3 cycles/degree.
  EXPECT_NEAR(larson_resolvable_frequency_cpd(100.0), 47.5, 0.05);
  EXPECT_NEAR(larson_resolvable_frequency_cpd(0.01), 5.3, 0.05);
  // Hand-computed: 17.25 atan(1.4 * 2 + 0.35) + 25.72.
  EXPECT_NEAR(larson_resolvable_frequency_cpd(100.0), 17.25 * std::atan(3.15) + 25.72, 1e-12);
}

TEST(PerceptionAcuity, ReferenceWhiteReproducesTheThesisLightnessAtItsHeadsetResolution) {
  // Eq. 5.17: R = 13.85 cycles/degree corresponds to "approximately 1.31 L". Invert Eq. 5.14 by hand:
  // log10 Y = (tan((R - 25.72) / 17.25) - 0.35) / 1.4.
  const double luminance = std::pow(10.0, (std::tan((13.85 - 25.72) / 17.25) - 0.35) / 1.4);
  EXPECT_NEAR(larson_resolvable_frequency_cpd(luminance), 13.85, 1e-12);
  const double lightness = lab_lightness(luminance, 100.0);
  std::printf("R = 13.85 cycles/degree at Y = %.5f cd/m2, L* = %.4f with Y_n = 100 cd/m2\n", luminance, lightness);
  EXPECT_NEAR(lightness, 1.31, 0.01);
  // L* = 903.3 Y / Y_n in the dark (CIE: (29/3)^3 = 903.296...).
  EXPECT_NEAR(lab_lightness(0.05, 100.0), std::pow(29.0 / 3.0, 3) * 0.0005, 1e-12);
  EXPECT_NEAR(luminance_of_lab_lightness(lab_lightness(37.0, 100.0), 100.0), 37.0, 1e-12);
}

TEST(PerceptionAcuity, LabRoundTripAndGreyAxis) {
  for (double grey : {0.001, 0.05, 3.0, 100.0, 5000.0}) {
    const LabColour lab = rec709_to_lab(grey, grey, grey, 100.0);
    EXPECT_NEAR(lab.a, 0.0, 1e-12);
    EXPECT_NEAR(lab.b, 0.0, 1e-12);
  }
  EXPECT_NEAR(rec709_to_lab(100.0, 100.0, 100.0, 100.0).lightness, 100.0, 1e-12);
  double rgb[3];
  lab_to_rec709(rec709_to_lab(0.02, 0.5, 7.0, 100.0), 100.0, rgb);
  EXPECT_NEAR(rgb[0], 0.02, 1e-12);
  EXPECT_NEAR(rgb[1], 0.5, 1e-12);
  EXPECT_NEAR(rgb[2], 7.0, 1e-12);
}

// A pixel's L* replaced with its a*, b* kept agrees with the round trip through LabColour, dark
// saturated pixels (off the linear branch in X or Z only) and bright ones alike.
TEST(PerceptionAcuity, ReplacedLightnessKeepsTheChromaticity) {
  const double pixels[][3] = {{0.02, 0.05, 0.07}, {0.001, 0.0, 0.3}, {0.09, 0.01, 0.0}, {20.0, 3.0, 0.5}};
  for (const auto& pixel : pixels)
    for (const double lightness : {0.2, 0.9, 45.0}) {
      LabColour lab = rec709_to_lab(pixel[0], pixel[1], pixel[2], 100.0);
      lab.lightness = lightness;
      double expected[3];
      lab_to_rec709(lab, 100.0, expected);
      float rgb[3] = {static_cast<float>(pixel[0]), static_cast<float>(pixel[1]), static_cast<float>(pixel[2])};
      const LabColour from_float = rec709_to_lab(rgb[0], rgb[1], rgb[2], 100.0);
      replace_lab_lightness(rgb, lightness, 100.0);
      const LabColour replaced = rec709_to_lab(rgb[0], rgb[1], rgb[2], 100.0);
      EXPECT_NEAR(replaced.lightness, lightness, 1e-5 * std::max(1.0, lightness));
      EXPECT_NEAR(replaced.a, from_float.a, 1e-4 * std::max(1.0, std::abs(from_float.a)));
      EXPECT_NEAR(replaced.b, from_float.b, 1e-4 * std::max(1.0, std::abs(from_float.b)));
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(rgb[c], expected[c], 1e-6 * std::max(1.0, std::abs(expected[c])));
    }
}

TEST(PerceptionAcuity, DisplayPixelsPerDegreeFromGeometry) {
  DisplaySpec display;
  display.viewing_distance_mm = 600.0;
  display.pixel_pitch_mm = 0.25;
  // One pixel subtends 2 atan(0.125 / 600) rad.
  EXPECT_NEAR(display_pixels_per_degree(display), 1.0 / (2.0 * std::atan(0.125 / 600.0) * 180.0 / kPi), 1e-9);
}

TEST(PerceptionAcuity, KernelNeverExceedsItsBound) {
  for (AcuitySigmaForm form : {AcuitySigmaForm::resolvable_frequency, AcuitySigmaForm::luidolt_linear}) {
    AcuitySettings settings;
    settings.sigma_form = form;
    for (double ppd : {5.0, kThesisPixelsPerDegree, 42.0, 120.0}) {
      double largest = 0.0;
      for (double lightness = -5.0; lightness <= 2.0; lightness += 1e-3) {
        const double sigma = acuity_sigma_px(lightness, settings, ppd);
        largest = std::max(largest, sigma);
        ASSERT_LE(sigma, 1.0) << "L* " << lightness << ", " << ppd << " px/deg";
        ASSERT_LE(acuity_kernel(sigma).size(), 7u) << "L* " << lightness << ", " << ppd << " px/deg";
        if (lightness >= 1.0) {
          ASSERT_EQ(sigma, 0.0) << "L* " << lightness;
        }
      }
      EXPECT_GT(largest, 0.5) << ppd;
    }
  }
  // Below R = 0 (Y < 6.5e-10 cd/m2) Eq. 5.15 has no meaning; the cap applies.
  EXPECT_EQ(acuity_sigma_px(0.0, AcuitySettings{}, 42.0), 1.0);
  // The kernel: exp(-k^2 / 2 sigma^2) normalised, radius floor(3 sigma).
  const std::vector<double> kernel = acuity_kernel(0.5);
  ASSERT_EQ(kernel.size(), 3u);
  const double edge = std::exp(-2.0);
  EXPECT_NEAR(kernel[0], edge / (1.0 + 2.0 * edge), 1e-15);
  EXPECT_NEAR(kernel[1], 1.0 / (1.0 + 2.0 * edge), 1e-15);
  EXPECT_EQ(acuity_kernel(1.0).size(), 7u);
  EXPECT_EQ(acuity_kernel(0.33).size(), 1u);
}

TEST(PerceptionAcuity, Eq515SigmaHandComputed) {
  // sigma_px = ppd / (1.86 sqrt(2) R(Y)) at L* = 0.5, Y = 0.5 / 903.296 * 100 cd/m2.
  const double luminance = 0.5 / std::pow(29.0 / 3.0, 3) * 100.0;
  const double resolvable = 17.25 * std::atan(1.4 * std::log10(luminance) + 0.35) + 25.72;
  AcuitySettings settings;
  settings.max_sigma_px = 10.0;
  EXPECT_NEAR(acuity_sigma_px(0.5, settings, kThesisPixelsPerDegree),
              kThesisPixelsPerDegree / (1.86 * std::sqrt(2.0) * resolvable), 1e-12);
  settings.sigma_form = AcuitySigmaForm::luidolt_linear;
  EXPECT_EQ(acuity_sigma_px(0.25, settings, kThesisPixelsPerDegree), 0.75);  // Eq. 5.16
}

ImageRGBA grey_image(int width, int height, const std::vector<double>& luminance) {
  ImageRGBA image(width, height, 0.0f);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float* p = image.pixel(x, y);
      p[0] = p[1] = p[2] = static_cast<float>(luminance[static_cast<std::size_t>(y) * width + x]);
      p[3] = 1.0f;
    }
  return image;
}

TEST(PerceptionAcuity, NoChangeWhereLightnessIsAtLeastOne) {
  // Alternating bright (0.2 cd/m2, L* = 1.8) and dark (0.001 cd/m2, L* = 0.009) pixels, and a pixel
  // exactly at the boundary L* = 1.
  const int width = 24, height = 16;
  std::vector<double> luminance(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) luminance[static_cast<std::size_t>(y) * width + x] = ((x + y) % 3 == 0) ? 0.2 : 0.001;
  luminance[5] = 100.0 / std::pow(29.0 / 3.0, 3);  // L* = 1
  const ImageRGBA input = grey_image(width, height, luminance);
  for (bool reference : {false, true}) {
    const ImageRGBA output = reference ? apply_acuity_loss_2d_reference(input, AcuitySettings{}, 42.0)
                                       : apply_acuity_loss(input, AcuitySettings{}, 42.0);
    int bright = 0, changed_dark = 0;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const float* in = input.pixel(x, y);
        const float* out = output.pixel(x, y);
        if (lab_lightness(in[1], 100.0) >= 1.0 - 1e-9) {
          ++bright;
          for (int c = 0; c < 4; ++c) ASSERT_EQ(out[c], in[c]) << x << "," << y;
        } else if (out[1] != in[1]) {
          ++changed_dark;
        }
      }
    EXPECT_GT(bright, 100);
    EXPECT_GT(changed_dark, 100);  // the dark pixels were blurred
  }
}

// Michelson contrast of the middle row's luminance, away from the borders.
double row_contrast(const ImageRGBA& image) {
  double lo = 1e300, hi = -1e300;
  const int y = image.height_px / 2;
  for (int x = 16; x < image.width_px - 16; ++x) {
    const double v = image.pixel(x, y)[1];
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  return (hi - lo) / (hi + lo);
}

TEST(PerceptionAcuity, GratingAboveResolvableFrequencyIsRemovedOneBelowSurvives) {
  // A mean luminance where Eq. 5.15 gives sigma = 0.98 px on the thesis' headset (uncapped):
  // R = ppd / (1.86 sqrt(2) 0.98), and Y from Eq. 5.14 inverted by hand.
  const double ppd = kThesisPixelsPerDegree;
  const double resolvable_cpd = ppd / (1.86 * std::sqrt(2.0) * 0.98);
  const double mean_cd_m2 = std::pow(10.0, (std::tan((resolvable_cpd - 25.72) / 17.25) - 0.35) / 1.4);
  const int width = 512, height = 8;
  for (double ratio : {1.2, 1.0 / 8.0}) {
    const double frequency_cpd = ratio * resolvable_cpd;
    const double period_px = ppd / frequency_cpd;
    std::vector<double> luminance(static_cast<std::size_t>(width) * height);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        luminance[static_cast<std::size_t>(y) * width + x] = mean_cd_m2 * (1.0 + 0.05 * std::cos(2.0 * kPi * x / period_px));
    const ImageRGBA input = grey_image(width, height, luminance);
    const ImageRGBA output = apply_acuity_loss(input, AcuitySettings{}, ppd);
    const double kept = row_contrast(output) / row_contrast(input);
    std::printf("grating at %.3f R (R = %.3f cycles/degree at %.5f cd/m2, period %.3f px): %.2f %% of its contrast kept\n",
                ratio, resolvable_cpd, mean_cd_m2, period_px, 100.0 * kept);
    if (ratio > 1.0)
      EXPECT_LT(kept, 0.05);
    else
      EXPECT_GT(kept, 0.90);
  }
}

TEST(PerceptionAcuity, Figure59NumbersReproduced) {
  // Fig. 5.9's 3 x 3 patch with Eq. 5.16's sigma (L* values as printed; 25 is bright, no blur).
  const std::vector<double> patch = {25.0, 0.9, 0.3, 0.9, 0.5, 0.6, 0.3, 0.6, 0.4};
  AcuitySettings settings;
  settings.sigma_form = AcuitySigmaForm::luidolt_linear;
  const double two_d = blur_lightness_2d(patch, 3, 3, settings, kThesisPixelsPerDegree)[4];
  settings.second_pass = SecondPassSigma::original_lightness;
  const double separable_figure = blur_lightness_separable(patch, 3, 3, settings, kThesisPixelsPerDegree)[4];
  settings.second_pass = SecondPassSigma::filtered_lightness;
  const double separable_text = blur_lightness_separable(patch, 3, 3, settings, kThesisPixelsPerDegree)[4];
  std::printf("Fig. 5.9 centre pixel: 2D %.4f (thesis 0.85), separable %.4f (thesis 0.59), separable with the "
              "second pass on the filtered lightness %.4f\n", two_d, separable_figure, separable_text);
  // By hand, sigma = 0.5: e = exp(-2) / (1 + 2 exp(-2)), c = 1 / (1 + 2 exp(-2)):
  // 2D = e^2 (25 + 0.3 + 0.3 + 0.4) + c e (0.9 + 0.9 + 0.6 + 0.6) + c^2 0.5.
  const double e = std::exp(-2.0) / (1.0 + 2.0 * std::exp(-2.0)), c = 1.0 / (1.0 + 2.0 * std::exp(-2.0));
  EXPECT_NEAR(two_d, e * e * 26.0 + c * e * 3.0 + c * c * 0.5, 1e-12);
  EXPECT_NEAR(two_d, 0.85, 0.01);
  EXPECT_NEAR(separable_figure, 0.59, 0.005);
  EXPECT_NEAR(separable_text, 0.58, 0.005);
}

TEST(PerceptionAcuity, SeparableEqualsTwoDWhereSigmaIsUniformAndErrsOnlyNearEdges) {
  // Dark noise (L* in [0, 0.5), every sigma at the 1 px cap at 42 px/deg) beside a bright block.
  const int width = 64, height = 48;
  std::vector<double> lightness(static_cast<std::size_t>(width) * height);
  unsigned state = 12345u;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      state = state * 1664525u + 1013904223u;
      const double noise = 0.5 * (state >> 8) / 16777216.0;
      lightness[static_cast<std::size_t>(y) * width + x] = x >= 40 ? 60.0 : noise;
    }
  const AcuitySettings settings;
  const std::vector<double> two_d = blur_lightness_2d(lightness, width, height, settings, 42.0);
  const std::vector<double> separable = blur_lightness_separable(lightness, width, height, settings, 42.0);
  double far_error = 0.0, edge_error = 0.0, edge_sum2 = 0.0;
  int edge_count = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * width + x;
      const double error = std::abs(separable[i] - two_d[i]);
      if (x < 40 - 6) {
        far_error = std::max(far_error, error);
      } else if (x < 40) {
        edge_error = std::max(edge_error, error);
        edge_sum2 += error * error;
        ++edge_count;
      }
    }
  std::printf("separable against 2D (L* units): max %.3g more than 6 px from the edge, max %.4f and rms %.4f within 6 px "
              "of a dark/bright edge (L* 0-0.5 against 60)\n", far_error, edge_error, std::sqrt(edge_sum2 / edge_count));
  EXPECT_LT(far_error, 1e-12);
  EXPECT_GT(edge_error, 1e-3);  // the comparison sees the edge
}

}  // namespace
}  // namespace glarelab

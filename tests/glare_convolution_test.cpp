// CPU convolution by FFT: delta gives back the PSF, energy conservation, no wrap-around, odd
// sizes, and the sun-next-to-a-dim-background case in float and double.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "glare/cpu/convolution.h"
#include "glare/cpu/psf.h"
#include "stimuli/display_model.h"

namespace glarelab {
namespace {

Psf test_psf(int grid_px) {
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 2.0;
  geometry.discs.push_back({0.3, 0.2, 0.2, 0.1});
  MonochromaticPsfOptions options;
  options.raster.grid_px = grid_px;
  options.raster.aperture_width_mm = 4.0;
  options.phase = PhaseForm::none;
  return compute_monochromatic_psf(geometry, options).psf;
}

// Direct (spatial) convolution: out(x, y) = sum_u,v img(x - u + M/2, y - v + M/2) psf(u, v).
std::vector<double> direct_convolution(const std::vector<double>& plane, int width, int height, const Psf& psf) {
  std::vector<double> out(plane.size(), 0.0);
  const int m = psf.size_px;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double value = plane[static_cast<std::size_t>(y) * width + x];
      if (value == 0.0) continue;
      for (int v = 0; v < m; ++v)
        for (int u = 0; u < m; ++u) {
          const int ox = x + u - m / 2, oy = y + v - m / 2;
          if (ox >= 0 && oy >= 0 && ox < width && oy < height) out[static_cast<std::size_t>(oy) * width + ox] += value * psf.at(0, u, v);
        }
    }
  return out;
}

TEST(GlareConvolution, DeltaGivesBackThePsf) {
  const Psf psf = test_psf(64);
  const int width = 101, height = 77;  // not powers of two
  std::vector<double> plane(static_cast<std::size_t>(width) * height, 0.0);
  const int cx = 50, cy = 38;
  plane[static_cast<std::size_t>(cy) * width + cx] = 1.0;
  const auto out = convolve_plane_cpu(plane, width, height, psf, 0, {});
  double worst = 0.0;
  for (int v = 0; v < 64; ++v)
    for (int u = 0; u < 64; ++u) {
      const int x = cx + u - 32, y = cy + v - 32;
      worst = std::max(worst, std::abs(out[static_cast<std::size_t>(y) * width + x] - psf.at(0, u, v)));
    }
  EXPECT_LT(worst, 1e-9);
  double total = 0.0;
  for (double v : out) total += v;
  EXPECT_NEAR(total, 1.0, 1e-9);  // the PSF fits inside: energy conserved
}

TEST(GlareConvolution, MatchesDirectSumWithoutWrapAtTheEdge) {
  // A source on the image edge: half its PSF falls outside and must vanish, not wrap to the far side.
  const Psf psf = test_psf(32);
  const int width = 45, height = 39;
  std::vector<double> plane(static_cast<std::size_t>(width) * height, 0.0);
  plane[static_cast<std::size_t>(10) * width + 0] = 5.0;
  plane[static_cast<std::size_t>(38) * width + 44] = 2.0;
  plane[static_cast<std::size_t>(20) * width + 20] = 1.0;
  const auto fft = convolve_plane_cpu(plane, width, height, psf, 0, {});
  const auto direct = direct_convolution(plane, width, height, psf);
  for (std::size_t k = 0; k < fft.size(); ++k) ASSERT_NEAR(fft[k], direct[k], 1e-12) << "pixel " << k;
}

TEST(GlareConvolution, ImageChannelsUseTheirPsfChannelAndKeepAlpha) {
  const Psf psf = test_psf(16);
  ImageRGBA image(20, 18, 0.0f);
  image.pixel(9, 9)[0] = 1.0f;
  image.pixel(9, 9)[1] = 2.0f;
  image.pixel(9, 9)[2] = 4.0f;
  for (int y = 0; y < 18; ++y)
    for (int x = 0; x < 20; ++x) image.pixel(x, y)[3] = 0.5f;
  const ImageRGBA out = convolve_image_cpu(image, psf, {});
  EXPECT_NEAR(out.pixel(9, 9)[0], psf.at(0, 8, 8), 1e-7);
  EXPECT_NEAR(out.pixel(9, 9)[2], 4.0 * psf.at(0, 8, 8), 4e-7);
  EXPECT_EQ(out.pixel(0, 0)[3], 0.5f);
}

TEST(GlareConvolution, RefusesNonFiniteAndNegativePixelsNamingTheCounts) {
  const Psf psf = test_psf(16);
  ImageRGBA image(20, 18, 1.0f);
  image.pixel(3, 4)[1] = std::numeric_limits<float>::quiet_NaN();
  image.pixel(5, 4)[0] = -1.0f;
  image.pixel(6, 4)[2] = -2.0f;
  try {
    convolve_image_cpu(image, psf, {});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("NaN"), std::string::npos) << message;
    EXPECT_NE(message.find("2 negative"), std::string::npos) << message;
  }
}

TEST(GlareConvolution, PsfAtDisplayScaleConservesEnergy) {
  // A 4 mm pupil PSF (0.0033 deg per pixel over 512 px = 1.7 deg) onto a display of 0.25 mm pixels
  // seen from 600 mm (0.0239 deg per pixel): the image of a few sources keeps its total, per channel.
  DisplaySpec spec;
  spec.pixel_pitch_mm = 0.25;
  spec.viewing_distance_mm = 600.0;
  const double display_degrees_per_pixel = DisplayModel(spec).degrees_per_pixel_at_centre();
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 4.0;
  MonochromaticPsfOptions options;
  options.raster.grid_px = 512;
  options.raster.aperture_width_mm = 10.0;
  options.wavelength_nm = 575.0;
  const Psf psf = compute_monochromatic_psf(geometry, options).psf;
  ImageRGBA image(301, 203, 0.0f);
  image.pixel(150, 100)[0] = 1000.0f;
  image.pixel(100, 80)[1] = 50.0f;
  image.pixel(200, 120)[2] = 7.0f;
  const ImageRGBA out = convolve_image_at_scale_cpu(image, display_degrees_per_pixel, psf, {});
  double sums[3] = {0, 0, 0};
  for (int y = 0; y < out.height_px; ++y)
    for (int x = 0; x < out.width_px; ++x)
      for (int c = 0; c < 3; ++c) sums[c] += out.pixel(x, y)[c];
  EXPECT_NEAR(sums[0] / 1000.0, 1.0, 1e-5);  // float image pixels
  EXPECT_NEAR(sums[1] / 50.0, 1.0, 1e-5);
  EXPECT_NEAR(sums[2] / 7.0, 1.0, 1e-5);
  EXPECT_GT(out.pixel(150, 100)[0], 100.0f);  // the core stays near the source's pixel
}

TEST(GlareConvolution, SunNextToDimBackgroundFloatNeedsTheBrightSplit) {
  // 1e8 cd/m2 source on a 1e-2 cd/m2 background; the dim region is outside the PSF's support
  // around the source, where the exact result is the convolved background alone.
  const Psf psf = test_psf(32);
  const int width = 200, height = 150;
  std::vector<double> plane(static_cast<std::size_t>(width) * height, 1e-2);
  plane[static_cast<std::size_t>(40) * width + 40] = 1e8;
  const auto reference = direct_convolution(plane, width, height, psf);
  auto dim_region_error = [&](const std::vector<double>& result) {
    double worst = 0.0;
    for (int y = 100; y < 140; ++y)
      for (int x = 120; x < 190; ++x) {
        const std::size_t k = static_cast<std::size_t>(y) * width + x;
        worst = std::max(worst, std::abs(result[k] - reference[k]) / reference[k]);
      }
    return worst;
  };
  ConvolutionOptions options;
  const double double_error = dim_region_error(convolve_plane_cpu(plane, width, height, psf, 0, options));
  options.precision = FftPrecision::float32;
  const double float_error = dim_region_error(convolve_plane_cpu(plane, width, height, psf, 0, options));
  options.bright_threshold = 1e3;
  ConvolutionReport report;
  const double split_error = dim_region_error(convolve_plane_cpu(plane, width, height, psf, 0, options, &report));
  std::printf("dim region max relative error: double %.3g, float %.3g, float with bright split %.3g (%zu bright px)\n",
              double_error, float_error, split_error, report.bright_pixels);
  // Double rounding: eps 1.1e-16 times the 1e10 dynamic range is ~1e-6 relative; 1e-4 leaves room.
  EXPECT_LT(double_error, 1e-4);
  EXPECT_GT(float_error, 1e-2);  // float alone swamps the background
  EXPECT_LT(split_error, 1e-2);
  EXPECT_EQ(report.bright_pixels, 1u);
}

}  // namespace
}  // namespace glarelab

// CIE 1931 CMF fit against the CIE table, and the spectral (chromatic blur) PSF.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "glare/wave/cie_cmf.h"
#include "glare/cpu/psf.h"
#include "glare/wave/spectral_psf.h"
#include "glare_psf_test_support.h"

namespace glarelab {
namespace {

TEST(GlareCieCmf, SpectralSamplesFollowSection5) {
  // Ritschel et al. 2009, section 5: lambda_i = 380 + i (770 - 380) / n nm; weights are the CMFs in
  // linear Rec.709. D65 white (X, Y, Z) = (0.95047, 1, 1.08883) is Rec.709 (1, 1, 1).
  const LinearRgb white = xyz_to_linear_rec709({0.95047, 1.0, 1.08883});
  EXPECT_NEAR(white.r, 1.0, 1e-3);
  EXPECT_NEAR(white.g, 1.0, 1e-3);
  EXPECT_NEAR(white.b, 1.0, 1e-3);
  const auto samples = spectral_samples(32);
  ASSERT_EQ(samples.size(), 32u);
  EXPECT_DOUBLE_EQ(samples.front().wavelength_nm, 380.0);
  EXPECT_DOUBLE_EQ(samples.back().wavelength_nm, 380.0 + 31.0 * 390.0 / 32.0);
  const LinearRgb expected = xyz_to_linear_rec709(cie1931_cmf(samples[10].wavelength_nm));
  EXPECT_EQ(samples[10].weight.g, expected.g);
  EXPECT_THROW(spectral_samples(0), std::invalid_argument);
}

TEST(GlareCieCmf, FitMatchesCie1931TableValues) {
  // CIE 1931 2-degree observer, 5 nm table (CIE 015:2018, Table B.1), hand-copied values. The
  // Wyman et al. 2013 multi-lobe fit is within a few percent of the peak (their Fig. 2): tolerance
  // 0.03 absolute, about 2% of zbar's peak of 1.78.
  struct Row {
    double wavelength_nm, x, y, z;
  };
  const Row rows[] = {
      {440.0, 0.34828, 0.02300, 1.74706}, {450.0, 0.33620, 0.03800, 1.77211}, {500.0, 0.00490, 0.32300, 0.27200},
      {555.0, 0.51205, 1.00000, 0.00575}, {600.0, 1.06220, 0.63100, 0.00080}, {650.0, 0.28350, 0.10700, 0.00002},
  };
  for (const Row& row : rows) {
    const Xyz fit = cie1931_cmf(row.wavelength_nm);
    EXPECT_NEAR(fit.x, row.x, 0.03) << row.wavelength_nm << " nm";
    EXPECT_NEAR(fit.y, row.y, 0.03) << row.wavelength_nm << " nm";
    EXPECT_NEAR(fit.z, row.z, 0.03) << row.wavelength_nm << " nm";
  }
}

TEST(GlareCieCmf, Rec709MatrixMapsD65WhiteToEqualRgb) {
  // D65 white point XYZ (0.9505, 1, 1.089) is R = G = B = 1 in linear Rec.709 (IEC 61966-2-1).
  const LinearRgb white = xyz_to_linear_rec709({0.9505, 1.0, 1.089});
  EXPECT_NEAR(white.r, 1.0, 2e-3);
  EXPECT_NEAR(white.g, 1.0, 2e-3);
  EXPECT_NEAR(white.b, 1.0, 2e-3);
}

Psf reference_psf() {
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 3.0;
  geometry.discs.push_back({0.6, -0.2, 0.25, 0.0});
  MonochromaticPsfOptions options;
  options.raster.grid_px = 256;
  options.raster.aperture_width_mm = 12.0;
  options.wavelength_nm = 575.0;
  options.phase = PhaseForm::none;
  return compute_monochromatic_psf(geometry, options).psf;
}

TEST(GlareSpectralPsf, ChannelsSumToOneAndAreNonNegative) {
  const Psf reference = reference_psf();
  const SpectralPsfResult result = spectral_psf_from_reference(reference, {});
  ASSERT_EQ(result.psf.channels, 3);
  EXPECT_EQ(result.psf.degrees_per_pixel, reference.degrees_per_pixel);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(test::channel_sum(result.psf, c), 1.0, 1e-9) << "channel " << c;
  for (double v : result.psf.values) ASSERT_GE(v, 0.0);
  std::printf("clamped negative fraction R %.4g G %.4g B %.4g\n", result.clamped_negative_fraction[0],
              result.clamped_negative_fraction[1], result.clamped_negative_fraction[2]);
  for (double fraction : result.clamped_negative_fraction) EXPECT_LT(fraction, 0.5);
}

TEST(GlareSpectralPsf, TwoSamplesMatchAnIndependentSum) {
  // n = 2: lambda = 380 nm (the reference shrunk by 380/575, Jacobian (575/380)^2) and 575 nm (the
  // reference itself). Rebuild R, G, B pixel by pixel from the CMFs and the Rec.709 matrix, clamp,
  // normalise, and compare everywhere.
  const Psf reference = reference_psf();
  SpectralPsfOptions options;
  options.wavelength_samples = 2;
  const SpectralPsfResult result = spectral_psf_from_reference(reference, options);
  const int n = reference.size_px;
  const Xyz w380 = cie1931_cmf(380.0), w575 = cie1931_cmf(575.0);
  std::vector<double> expected(3 * static_cast<std::size_t>(n) * n);
  double sums[3] = {0, 0, 0};
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double s = 575.0 / 380.0;
      const double f380 = s * s * test::bilinear(reference, 0, (x - n / 2) * s + n / 2, (y - n / 2) * s + n / 2);
      const double f575 = reference.at(0, x, y);
      const LinearRgb rgb = xyz_to_linear_rec709({w380.x * f380 + w575.x * f575, w380.y * f380 + w575.y * f575,
                                                  w380.z * f380 + w575.z * f575});
      const double channel[3] = {rgb.r, rgb.g, rgb.b};
      for (int c = 0; c < 3; ++c) {
        const double clamped = std::max(0.0, channel[c]);
        expected[(static_cast<std::size_t>(c) * n + y) * n + x] = clamped;
        sums[c] += clamped;
      }
    }
  double worst = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        worst = std::max(worst, std::abs(result.psf.at(c, x, y) - expected[(static_cast<std::size_t>(c) * n + y) * n + x] / sums[c]));
  EXPECT_LT(worst, 1e-12);
}

TEST(GlareSpectralPsf, RefusesAChannelWithNoLight) {
  // n = 1 samples only 380 nm, whose Rec.709 green is negative everywhere: green cannot sum to 1.
  SpectralPsfOptions options;
  options.wavelength_samples = 1;
  EXPECT_THROW(spectral_psf_from_reference(reference_psf(), options), std::runtime_error);
}

}  // namespace
}  // namespace glarelab

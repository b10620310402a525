// The spectral PSF with a refraction and longitudinal chromatic aberration (glare/wave/chromatic_psf.h):
// one FFT per wavelength. Without a phase it must be Ritschel's scaled-reference spectral PSF (the
// scaling is exact in the Fraunhofer case); with a myope's error its R and B blur must differ as
// Thibos' formula says.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "glare/refraction/chromatic_eye.h"
#include "glare/wave/chromatic_psf.h"
#include "glare/wave/cie_cmf.h"
#include "glare/cpu/psf.h"
#include "glare/wave/spectral_psf.h"
#include "glare_refraction_test_support.h"

namespace glarelab {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

ChromaticPsfOptions chromatic_options(int grid_px, double width_mm, int samples) {
  ChromaticPsfOptions options;
  options.raster.grid_px = grid_px;
  options.raster.aperture_width_mm = width_mm;
  options.wavelength_samples = samples;
  options.reference_wavelength_nm = 575.0;
  return options;
}

TEST(GlareChromaticPsf, WithoutPhaseItIsTheScaledReferenceSpectralPsf) {
  // In focus and without LCA every wavelength's PSF, in its own pixels of lambda / W, is the reference
  // PSF itself: the two spectral PSFs are the same sums.
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 3.0;
  ChromaticPsfOptions options = chromatic_options(128, 8.0, 8);
  options.longitudinal_chromatic_aberration = false;
  const ChromaticPsfResult chromatic = compute_chromatic_psf(geometry, options);

  MonochromaticPsfOptions mono;
  mono.raster = options.raster;
  mono.wavelength_nm = 575.0;
  SpectralPsfOptions spectral;
  spectral.wavelength_samples = 8;
  const SpectralPsfResult scaled = spectral_psf_from_reference(compute_monochromatic_psf(geometry, mono).psf, spectral);
  ASSERT_EQ(chromatic.spectral.psf.values.size(), scaled.psf.values.size());
  for (std::size_t k = 0; k < scaled.psf.values.size(); ++k)
    ASSERT_NEAR(chromatic.spectral.psf.values[k], scaled.psf.values[k], 1e-12) << k;
  EXPECT_EQ(chromatic.spectral.psf.degrees_per_pixel, scaled.psf.degrees_per_pixel);
}

TEST(GlareChromaticPsf, PerWavelengthErrorAddsThibosLca) {
  const ChromaticPsfOptions options = chromatic_options(64, 8.0, 8);
  const DioptricPower myope = DioptricPower::spherical(2.0);
  const DioptricPower at_400 = chromatic_power_error(myope, 400.0, options);
  EXPECT_NEAR(at_400.xx(), 2.0 + chromatic_refraction_dioptres(575.0) - chromatic_refraction_dioptres(400.0), 1e-12);
  const DioptricPower difference = chromatic_power_error(myope, 400.0, options) - chromatic_power_error(myope, 700.0, options);
  EXPECT_NEAR(difference.xx(), 2.1038, 1e-4);  // Thibos: 2.10 D between 400 and 700 nm
  EXPECT_NEAR(difference.xy(), 0.0, 1e-15);
}

TEST(GlareChromaticPsf, MyopeBlursBlueMoreThanRedAsThibosSays) {
  // A 2 D myope (at 575 nm), 4 mm pupil: at lambda the error is 2 D + LCA excess, whose geometric blur
  // is a disc of radius |E(lambda)| r with <x^2> = (E r)^2 / 4. The PSF's second moment is that plus
  // the in-focus (diffraction) PSF's: for a real pupil A, |grad(A exp(i phi))|^2 = |grad A|^2 +
  // A^2 |grad phi|^2, so the two add. A channel mixes the wavelengths with its CMF weights in Rec.709
  // (w_c(lambda), glare/wave/cie_cmf.h), so its geometric part is predicted as sum w_c <x^2>_lambda / sum w_c
  // (negative weights included; the clamping of negative pixels moves it a little), and its
  // diffraction part is measured on the same eye in focus.
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 4.0;
  const int samples = 16;
  const ChromaticPsfOptions options = chromatic_options(512, 8.0, samples);
  const ChromaticPsfResult in_focus = compute_chromatic_psf(geometry, [&] {
    ChromaticPsfOptions no_lca = options;
    no_lca.longitudinal_chromatic_aberration = false;
    return no_lca;
  }());
  geometry.refraction_error = DioptricPower::spherical(2.0);
  const ChromaticPsfResult result = compute_chromatic_psf(geometry, options);
  ASSERT_TRUE(result.sampling_warning.empty()) << result.sampling_warning;
  const double radius_m = 2e-3;
  double predicted[3] = {0, 0, 0}, weights[3] = {0, 0, 0};
  for (const SpectralSample& sample : spectral_samples(samples)) {
    const double error = 2.0 + chromatic_power_excess_dioptres(sample.wavelength_nm, 575.0);
    const double second_moment = std::pow(error * radius_m * kDegPerRad, 2) / 4.0;
    const double w[3] = {sample.weight.r, sample.weight.g, sample.weight.b};
    for (int c = 0; c < 3; ++c) {
      predicted[c] += w[c] * second_moment;
      weights[c] += w[c];
    }
  }
  double geometric[3];
  for (int c = 0; c < 3; ++c) {
    predicted[c] /= weights[c];
    const test::PsfMoments moments = test::psf_moments(result.spectral.psf, c);
    const test::PsfMoments focus = test::psf_moments(in_focus.spectral.psf, c);
    geometric[c] = 0.5 * (moments.xx_deg2 + moments.yy_deg2) - 0.5 * (focus.xx_deg2 + focus.yy_deg2);
    std::cout << "channel " << "RGB"[c] << ": rms blur radius " << std::sqrt(2.0 * geometric[c])
              << " deg (diffraction removed), predicted " << std::sqrt(2.0 * predicted[c]) << " deg (clamped "
              << result.spectral.clamped_negative_fraction[c] << ")\n";
    EXPECT_NEAR(geometric[c] / predicted[c], 1.0, 0.10) << "channel " << c;
  }
  // Blue blurs more than red for a myope, by the ratio the formula gives.
  const double ratio = std::sqrt(geometric[2] / geometric[0]), expected = std::sqrt(predicted[2] / predicted[0]);
  std::cout << "blue / red blur: " << ratio << ", Thibos " << expected << "\n";
  EXPECT_GT(ratio, 1.4);
  EXPECT_NEAR(ratio / expected, 1.0, 0.05);
}

}  // namespace
}  // namespace glarelab

// The GL spectral PSF with the eye's longitudinal chromatic aberration (GlPsf::chromatic) against
// the CPU float64 reference compute_chromatic_psf (glare/wave/chromatic_psf.h: one FFT per wavelength
// with E + [LCA(lambda) - LCA(lambda_ref)] I, resampled and CMF-weighted by
// glare/wave/spectral_accumulation.h), per channel, relative to the peak and in L2, for a myope, an
// oblique astigmat and an emmetrope; and the emmetrope's blue and red channel widths, which the
// scaled-reference spectral PSF gets the wrong way round.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <vector>

#include "glare/wave/chromatic_psf.h"
#include "glare/gl/psf.h"
#include "runner/display/compute_context.h"
#include "psf_agreement.h"

namespace glarelab {
namespace {

using test::Agreement;
using test::compare_channel;
using test::rms_radius_px;

class GlChromaticTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { context_ = gl::create_compute_context(); }
  static void TearDownTestSuite() { context_.reset(); }
  static std::unique_ptr<DisplayBackend> context_;
};
std::unique_ptr<DisplayBackend> GlChromaticTest::context_;

// 512 px over 8 mm with a 4 mm pupil: the strongest phase below (+2.5 D plus the eye's +2.06 D at
// 380 nm) steps 2.3 rad per pixel at the pupil's edge, under the pi of the sampling check, at every
// wavelength.
constexpr int kGridPx = 512;
constexpr double kWidthMm = 8.0, kPupilMm = 4.0, kReferenceNm = 575.0;
constexpr int kWavelengths = 16;

// An uncorrected eye looking far: its residual error is minus its correcting prescription (positive
// = too much power, glare/refraction/eye_refraction.h), here without vertex distance.
ApertureGeometry eye_with_prescription(const SpheroCylinder& prescription) {
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = kPupilMm;
  geometry.refraction_error = DioptricPower::from_prescription(prescription) * -1.0;
  return geometry;
}

ChromaticPsfResult reference(const ApertureGeometry& geometry, int wavelengths = kWavelengths, int grid_px = kGridPx) {
  ChromaticPsfOptions options;
  options.raster.grid_px = grid_px;
  options.raster.aperture_width_mm = kWidthMm;
  options.raster.supersampling = 2;
  options.reference_wavelength_nm = kReferenceNm;
  options.wavelength_samples = wavelengths;
  return compute_chromatic_psf(geometry, options);
}

TEST_F(GlChromaticTest, MatchesTheFloat64ReferenceForAMyopeAnObliqueAstigmatAndAnEmmetrope) {
  struct Eye {
    const char* name;
    SpheroCylinder prescription;
  };
  const Eye eyes[] = {{"myope -2", {-2.0, 0.0, 0.0}}, {"astigmat -1 / -1.5 x 30", {-1.0, -1.5, 30.0}},
                      {"emmetrope", {0.0, 0.0, 0.0}}};
  gl::GlPsf gl_psf(kGridPx, kWidthMm, 2);
  for (const Eye& eye : eyes) {
    const ApertureGeometry geometry = eye_with_prescription(eye.prescription);
    const ChromaticPsfResult expected = reference(geometry);
    ASSERT_EQ(expected.aliased_wavelengths, 0) << eye.name << ": " << expected.sampling_warning;
    const Psf psf = gl_psf.chromatic(geometry, kWavelengths, kReferenceNm);
    EXPECT_EQ(gl_psf.chromatic_aliased_wavelengths(), 0);
    EXPECT_TRUE(gl_psf.chromatic_sampling_warning().empty());
    ASSERT_EQ(psf.channels, 3);
    ASSERT_EQ(psf.size_px, kGridPx);
    EXPECT_NEAR(psf.degrees_per_pixel, expected.spectral.psf.degrees_per_pixel, 1e-12);
    for (int c = 0; c < 3; ++c) {
      const Agreement agreement = compare_channel(psf, expected.spectral.psf, c);
      double sum = 0.0;
      for (std::size_t k = c * psf.values.size() / 3; k < (c + 1) * psf.values.size() / 3; ++k) sum += psf.values[k];
      std::printf("GL chromatic %-26s channel %c: max error / peak %.2e, relative L2 %.2e, sum %.7f\n", eye.name,
                  "RGB"[c], agreement.max_over_peak, agreement.relative_l2, sum);
      // The GL PSF's tolerance against its double reference with a refraction
      // (glare_gl_astigmatic_test: 1e-5 of the peak, 1e-5 relative L2), here per channel. Measured
      // 1e-6 to 4e-6: float32 FFTs, float accumulation over the wavelengths and the resampling
      // position (N/2 + offset lambda_ref / lambda) rounded to float.
      EXPECT_LT(agreement.max_over_peak, 1e-5) << eye.name << " channel " << c;
      EXPECT_LT(agreement.relative_l2, 1e-5) << eye.name << " channel " << c;
      EXPECT_NEAR(sum, 1.0, 1e-5) << eye.name << " channel " << c;
    }
  }
}

TEST_F(GlChromaticTest, LcaAloneBlursBlueMoreThanRedAsTheReferenceSays) {
  // An emmetrope at 575 nm: without LCA every wavelength is in focus and the channels differ only by
  // diffraction (a PSF pixel scales with lambda, so red is the wider); with it the eye is 1-1.4 D
  // myopic across the blue channel's wavelengths and 0.2-0.4 D hyperopic across the red's, so blue is
  // several times wider than red.
  const ApertureGeometry emmetrope = eye_with_prescription({0.0, 0.0, 0.0});
  const Psf expected = reference(emmetrope).spectral.psf;
  gl::GlPsf gl_psf(kGridPx, kWidthMm, 2);
  const Psf with_lca = gl_psf.chromatic(emmetrope, kWavelengths, kReferenceNm);
  const Psf scaled = gl_psf.spectral(emmetrope, kWavelengths, kReferenceNm);
  const double expected_ratio = rms_radius_px(expected, 2) / rms_radius_px(expected, 0);
  const double gl_ratio = rms_radius_px(with_lca, 2) / rms_radius_px(with_lca, 0);
  const double scaled_ratio = rms_radius_px(scaled, 2) / rms_radius_px(scaled, 0);
  std::printf("emmetrope rms radius blue / red: reference %.4f, GL with LCA %.4f, GL scaled reference %.4f\n",
              expected_ratio, gl_ratio, scaled_ratio);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(rms_radius_px(with_lca, c) / rms_radius_px(expected, c), 1.0, 1e-4) << "channel " << c;
  EXPECT_GT(expected_ratio, 1.5);
  EXPECT_NEAR(gl_ratio / expected_ratio, 1.0, 1e-4);
  EXPECT_LT(scaled_ratio, 1.0);
}

TEST_F(GlChromaticTest, ReportsTheAliasedWavelengthsAsTheReferenceDoes) {
  // At N = 256 over 8 mm the blue end of a -2 D myope's and a -1 / -1.5 x 30 astigmat's spectrum
  // aliases (the eye's LCA adds up to +2.06 D at 380 nm); the emmetrope's does not.
  gl::GlPsf gl_psf(256, kWidthMm, 2);
  for (const SpheroCylinder& prescription : {SpheroCylinder{-2.0, 0.0, 0.0}, SpheroCylinder{-1.0, -1.5, 30.0},
                                             SpheroCylinder{0.0, 0.0, 0.0}}) {
    const ApertureGeometry geometry = eye_with_prescription(prescription);
    const ChromaticPsfResult expected = reference(geometry, kWavelengths, 256);
    (void)gl_psf.chromatic(geometry, kWavelengths, kReferenceNm);
    EXPECT_EQ(gl_psf.chromatic_aliased_wavelengths(), expected.aliased_wavelengths);
    EXPECT_EQ(gl_psf.chromatic_sampling_warning(), expected.sampling_warning);
    std::printf("N = 256, %+.1f / %+.1f x %.0f: %d aliased wavelengths; %s\n", prescription.sphere_dioptres,
                prescription.cylinder_dioptres, prescription.axis_deg, gl_psf.chromatic_aliased_wavelengths(),
                gl_psf.chromatic_sampling_warning().c_str());
    if (prescription.sphere_dioptres != 0.0) EXPECT_GT(expected.aliased_wavelengths, 0);
    else EXPECT_EQ(expected.aliased_wavelengths, 0);
  }
}

TEST_F(GlChromaticTest, ScaledReferenceSpectralPsfIsUnchangedByTheChromaticPath) {
  // The scaled-reference path stays the default and keeps its result bit for bit whatever ran
  // before it on the same GlPsf.
  ApertureGeometry geometry = eye_with_prescription({-1.0, -0.5, 120.0});
  geometry.discs = {{0.5, 0.4, 0.2, 0.3}};
  gl::GlPsf gl_psf(128, kWidthMm, 2);
  const Psf before = gl_psf.spectral(geometry, 8, kReferenceNm);
  (void)gl_psf.chromatic(geometry, 8, kReferenceNm);
  const Psf after = gl_psf.spectral(geometry, 8, kReferenceNm);
  EXPECT_EQ(before.values, after.values);
  // And the chromatic PSF is itself deterministic.
  EXPECT_EQ(gl_psf.chromatic(geometry, 8, kReferenceNm).values, gl_psf.chromatic(geometry, 8, kReferenceNm).values);
}

TEST_F(GlChromaticTest, RefusesBadWavelengthsBeforeDrawing) {
  gl::GlPsf gl_psf(64, kWidthMm, 2);
  const ApertureGeometry geometry = eye_with_prescription({-2.0, 0.0, 0.0});
  EXPECT_THROW(gl_psf.chromatic(geometry, 0, kReferenceNm), std::invalid_argument);
  EXPECT_THROW(gl_psf.chromatic(geometry, 8, 0.0), std::invalid_argument);
  EXPECT_THROW(gl_psf.chromatic(geometry, 8, 200.0), std::invalid_argument);  // at or below the LCA fit's pole
}

}  // namespace
}  // namespace glarelab

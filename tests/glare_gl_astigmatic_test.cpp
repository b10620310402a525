// The GL PSF with an astigmatic (sphero-cylindrical) power error: the pupil function and the PSF
// against a CPU double reference built here from glare/refraction/astigmatic_phase.h's apply_power_error_phase
// and glare/cpu/psf.h's shifted_power_spectrum on the same rasterised aperture; the PSF's second moments
// against the geometric blur E (r^2 / 4) E^T; a spherical error bit for bit as a defocus.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "glare/refraction/astigmatic_phase.h"
#include "glare/gl/cross_phase_turns.h"
#include "glare/gl/backend.h"
#include "glare/gl/psf.h"
#include "glare/cpu/psf.h"
#include "runner/display/compute_context.h"
#include "psf_agreement.h"

namespace glarelab {
namespace {

using test::Agreement;
using test::compare;

class GlAstigmaticTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { context_ = gl::create_compute_context(); }
  static void TearDownTestSuite() { context_.reset(); }
  static std::unique_ptr<DisplayBackend> context_;
};
std::unique_ptr<DisplayBackend> GlAstigmaticTest::context_;

// Prescriptions with oblique axes (TABO 30, 45, 120, 70) and a mixed astigmatism (+1 / -2.5: one
// principal meridian hyperopic, the other myopic), added to the geometry's own defocus.
const SpheroCylinder kPrescriptions[] = {{0.0, -1.5, 30.0}, {-0.5, -2.0, 45.0}, {0.75, -1.25, 120.0}, {1.0, -2.5, 70.0}};

ApertureGeometry busy_eye(double pupil_mm, const SpheroCylinder& prescription) {
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = pupil_mm;
  geometry.defocus_dioptres = 0.25;
  geometry.refraction_error = DioptricPower::from_prescription(prescription);
  geometry.discs = {{1.0, 0.5, 0.3, 0.2}, {-1.5, -1.0, 0.6, 0.0}};
  geometry.lines = {{-2.0, 1.5, 2.0, 0.5, 0.1, 0.3}};
  return geometry;
}

// The aperture GlPsf draws, read back from a GlAperture given the same geometry, as an ApertureGrid.
ApertureGrid gl_aperture_grid(const ApertureGeometry& geometry, int n, double width_mm, int supersampling) {
  gl::GlAperture aperture(n, width_mm, supersampling);
  aperture.draw(geometry);
  const std::vector<float> values = aperture.read();
  ApertureGrid grid;
  grid.grid_px = n;
  grid.aperture_width_mm = width_mm;
  grid.transmittance.assign(values.begin(), values.end());
  return grid;
}

std::vector<double> normalised(std::vector<double> power) {
  double sum = 0.0;
  for (double p : power) sum += p;
  for (double& p : power) p /= sum;
  return power;
}

double max_field_error(const std::vector<std::complex<float>>& test, const std::vector<std::complex<double>>& reference) {
  double worst = 0.0;
  for (std::size_t k = 0; k < reference.size(); ++k)
    worst = std::max(worst, std::abs(std::complex<double>(test[k]) - reference[k]));
  return worst;
}

// Central second moments of a one-channel PSF in the observer frame (x right, y up; row 0 at the
// top), in rad^2: {xx, xy, yy}.
struct Moments {
  double xx = 0.0, xy = 0.0, yy = 0.0;
};
Moments second_moments(const Psf& psf) {
  const int n = psf.size_px;
  const double step_rad = psf.degrees_per_pixel * std::numbers::pi / 180.0;
  double sum = 0.0, mx = 0.0, my = 0.0;
  for (int py = 0; py < n; ++py)
    for (int px = 0; px < n; ++px) {
      const double w = psf.at(0, px, py), x = (px - n / 2) * step_rad, y = (n / 2 - py) * step_rad;
      sum += w, mx += w * x, my += w * y;
    }
  mx /= sum, my /= sum;
  Moments m;
  for (int py = 0; py < n; ++py)
    for (int px = 0; px < n; ++px) {
      const double w = psf.at(0, px, py) / sum, x = (px - n / 2) * step_rad - mx, y = (n / 2 - py) * step_rad - my;
      m.xx += w * x * x, m.xy += w * x * y, m.yy += w * y * y;
    }
  return m;
}

TEST(GlCrossPhaseTurns, FixedPointFractionByHand) {
  using gl::fixed_point_fraction;
  EXPECT_EQ(fixed_point_fraction(0.25).high, 0x40000000u);
  EXPECT_EQ(fixed_point_fraction(0.25).low, 0u);
  EXPECT_EQ(fixed_point_fraction(-0.25).high, 0xC0000000u);  // -1/4 turn = 3/4 turn
  EXPECT_EQ(fixed_point_fraction(1.75).high, 0xC0000000u);   // whole turns drop out
  EXPECT_EQ(fixed_point_fraction(std::ldexp(1.0, -40)).high, 0u);
  EXPECT_EQ(fixed_point_fraction(std::ldexp(1.0, -40)).low, 1u << 24);
  EXPECT_EQ(fixed_point_fraction(-std::ldexp(1.0, -40)).high, 0xFFFFFFFFu);  // 2^64 - 2^24
  EXPECT_EQ(fixed_point_fraction(-std::ldexp(1.0, -40)).low, 0xFF000000u);
  EXPECT_EQ(fixed_point_fraction(3.0).high, 0u);
  EXPECT_EQ(fixed_point_fraction(3.0).low, 0u);
  // b = E_xy dx^2 / lambda: 1 D, 10 um, 500 nm -> 1e-10 / 5e-7 = 2e-4 turns.
  EXPECT_DOUBLE_EQ(gl::cross_phase_turns_per_index(1.0, 0.01, 500.0), 2e-4);
}

TEST_F(GlAstigmaticTest, FieldAndPsfMatchTheDoubleReferenceForObliqueAndMixedPrescriptions) {
  const int n = 256;
  const double width_mm = 10.0, pupil_mm = 5.0, wavelength_nm = 600.0;
  gl::GlPsf gl_psf(n, width_mm, 2);
  for (const SpheroCylinder& prescription : kPrescriptions) {
    const ApertureGeometry geometry = busy_eye(pupil_mm, prescription);
    ASSERT_TRUE(geometry.astigmatic());
    const DioptricPower error = geometry.total_power_error();
    ASSERT_FALSE(check_power_error_sampling(error, wavelength_nm, 0.5 * pupil_mm, width_mm / n, width_mm).aliased);
    const ApertureGrid grid = gl_aperture_grid(geometry, n, width_mm, 2);
    const std::vector<std::complex<double>> field = apply_power_error_phase(grid, error, wavelength_nm);
    const std::vector<double> expected = normalised(shifted_power_spectrum(field, n, FftPrecision::float64));

    gl_psf.load_field(geometry, wavelength_nm);
    const double field_error = max_field_error(gl_psf.read_field(), field);
    const Psf psf = gl_psf.monochromatic(geometry, wavelength_nm);
    const Agreement agreement = compare(psf.values, expected);
    std::printf("GL astigmatic %+.2f / %+.2f x %3.0f: field max error %.2e, PSF max error / peak %.2e, relative L2 %.2e\n",
                prescription.sphere_dioptres, prescription.cylinder_dioptres, prescription.axis_deg, field_error,
                agreement.max_over_peak, agreement.relative_l2);
    // Float32 factors (3 complex products) against double: a few float ulps of the unit amplitude.
    EXPECT_LT(field_error, 1e-6);
    // The GL FFT's own error on a defocused busy aperture is 1e-7 relative L2 (glare_gl_psf_test).
    EXPECT_LT(agreement.max_over_peak, 1e-5);
    EXPECT_LT(agreement.relative_l2, 1e-5);
  }
}

TEST_F(GlAstigmaticTest, LargeCrossPhasesAreReducedExactly) {
  // +1 / -6 x 45 over a 9 mm pupil at N = 1024: E_xy = -3 D, the cross phase E_xy x y / lambda
  // reaches 53 turns and |k| = |(i - N/2)(N/2 - j)| reaches 2^18. The phase aliases on this grid
  // (the field is still the sampled function, which is what is compared).
  const int n = 1024;
  const double width_mm = 10.0, wavelength_nm = 575.0;
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 9.0;
  geometry.refraction_error = DioptricPower::from_prescription({1.0, -6.0, 45.0});
  const DioptricPower error = geometry.total_power_error();
  gl::GlPsf gl_psf(n, width_mm, 2);
  gl_psf.load_field(geometry, wavelength_nm);
  const ApertureGrid grid = gl_aperture_grid(geometry, n, width_mm, 2);
  const double field_error = max_field_error(gl_psf.read_field(), apply_power_error_phase(grid, error, wavelength_nm));

  // What a float product b k (then fract, then float cos/sin) would give for the cross factor alone,
  // against double, over the pupil: the reason for the integer reduction, and proof that the bound
  // below would catch it.
  const double b = gl::cross_phase_turns_per_index(error.xy(), width_mm / n, wavelength_nm);
  double float_product_error = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (grid.transmittance[static_cast<std::size_t>(j) * n + i] == 0.0) continue;
      const int k = (i - n / 2) * (n / 2 - j);
      const float turns = static_cast<float>(b) * static_cast<float>(k);
      const float reduced = turns - std::floor(turns);
      const std::complex<double> in_float(std::cos(6.2831853f * reduced), std::sin(6.2831853f * reduced));
      const std::complex<double> exact = std::polar(1.0, 2.0 * std::numbers::pi * std::fmod(b * k, 1.0));
      float_product_error = std::max(float_product_error, std::abs(in_float - exact));
    }
  std::printf("GL astigmatic +1 / -6 x 45, 9 mm pupil, N = 1024: field max error %.2e (a float product b k: %.2e)\n",
              field_error, float_product_error);
  EXPECT_LT(field_error, 1e-6);
  EXPECT_GT(float_product_error, 5e-6);
}

TEST_F(GlAstigmaticTest, SecondMomentsAreThePupilMappedByThePowerError) {
  // Geometric optics: the ray through pupil point p leaves at angle E p, so the PSF is the pupil
  // disc mapped by E (glare/refraction/dioptric_power.h, geometric_blur_ellipse), with covariance
  // E (r^2 / 4 I) E^T for a uniform disc of radius r. Diffraction adds a term that is isotropic for
  // a round pupil (the disc is symmetric under x <-> y and x -> -x on the grid), so xy and xx - yy
  // are the geometric ones. Dropping the cross term would give E' = diag(E_xx, E_yy) and xy = 0.
  const int n = 512;
  const double width_mm = 10.0, pupil_mm = 4.0, wavelength_nm = 575.0, r_m = 0.5 * pupil_mm * 1e-3;
  gl::GlPsf gl_psf(n, width_mm, 4);
  for (const SpheroCylinder& prescription :
       {SpheroCylinder{0.0, -2.0, 45.0}, SpheroCylinder{-1.0, -1.5, 30.0}, SpheroCylinder{1.0, -2.5, 120.0}}) {
    ApertureGeometry geometry;
    geometry.pupil_diameter_mm = pupil_mm;
    geometry.refraction_error = DioptricPower::from_prescription(prescription);
    const glm::dmat2 e = geometry.total_power_error().matrix_dioptres;
    const glm::dmat2 predicted = e * (0.25 * r_m * r_m) * glm::transpose(e);
    const Moments measured = second_moments(gl_psf.monochromatic(geometry, wavelength_nm));
    const double scale = 0.25 * r_m * r_m * (e[0][0] * e[0][0] + 2.0 * e[1][0] * e[1][0] + e[1][1] * e[1][1]);
    std::printf("GL moments %+.2f / %+.2f x %3.0f: xy %.4e (predicted %.4e), xx - yy %.4e (predicted %.4e) rad^2\n",
                prescription.sphere_dioptres, prescription.cylinder_dioptres, prescription.axis_deg, measured.xy,
                predicted[1][0], measured.xx - measured.yy, predicted[0][0] - predicted[1][1]);
    ASSERT_GT(std::abs(predicted[1][0]), 0.1 * scale);  // the cross term matters here
    EXPECT_NEAR(measured.xy, predicted[1][0], 0.02 * scale);
    EXPECT_NEAR(measured.xx - measured.yy, predicted[0][0] - predicted[1][1], 0.02 * scale);
  }
}

TEST_F(GlAstigmaticTest, SphericalErrorsAreTheDefocusPathBitForBit) {
  // A spherical refraction error adds to the defocus: the field and the PSF are those of a geometry
  // with the summed defocus and no refraction, bit for bit (the same shader, the same factors).
  const int n = 128;
  gl::GlPsf gl_psf(n, 10.0, 2);
  ApertureGeometry with_refraction = busy_eye(5.0, {});
  with_refraction.defocus_dioptres = 0.5;
  with_refraction.refraction_error = DioptricPower::spherical(0.25);
  ASSERT_FALSE(with_refraction.astigmatic());
  ApertureGeometry defocus_only = with_refraction;
  defocus_only.refraction_error = DioptricPower{};
  defocus_only.defocus_dioptres = 0.75;
  const Psf a = gl_psf.monochromatic(with_refraction, 575.0);
  const Psf b = gl_psf.monochromatic(defocus_only, 575.0);
  EXPECT_TRUE(a.values == b.values);
  const Psf spectral_a = gl_psf.spectral(with_refraction, 8, 575.0);
  const Psf spectral_b = gl_psf.spectral(defocus_only, 8, 575.0);
  EXPECT_TRUE(spectral_a.values == spectral_b.values);
  // And an astigmatic error does change it.
  ApertureGeometry astigmatic = defocus_only;
  astigmatic.refraction_error = DioptricPower::from_prescription({0.0, -0.5, 45.0});
  EXPECT_FALSE(gl_psf.monochromatic(astigmatic, 575.0).values == b.values);
}

TEST_F(GlAstigmaticTest, RefusesWavelengthsThatAreNotPositive) {
  gl::GlPsf gl_psf(64, 8.0, 2);
  const ApertureGeometry geometry = busy_eye(4.0, {0.0, -1.0, 30.0});
  EXPECT_THROW(gl_psf.load_field(geometry, 0.0), std::invalid_argument);
  EXPECT_THROW(gl_psf.load_field(geometry, std::nan("")), std::invalid_argument);
  EXPECT_THROW(gl_psf.apply_phase(geometry.total_power_error(), -575.0), std::invalid_argument);
}

TEST_F(GlAstigmaticTest, BackendUsesTheWholeErrorAndChecksItsSampling) {
  GlareBackendSettings settings;
  settings.gl_context = gl::compute_context_factory();
  gl::GlGlareBackend backend(settings.gl_context());
  PsfOptions options;
  options.grid_px = 128;
  options.aperture_width_mm = 10.0;
  ApertureGeometry geometry = busy_eye(5.0, {0.0, -1.0, 30.0});
  gl::GlPsf direct(128, 10.0, 2);
  EXPECT_TRUE(backend.psf(geometry, options).values == direct.monochromatic(geometry, 575.0).values);
  EXPECT_EQ(backend.last_warning(), "");
  // Fraunhofer: no phase at all, neither the defocus nor the refraction.
  options.phase = PhaseForm::none;
  ApertureGeometry clear = geometry;
  clear.defocus_dioptres = 0.0;
  clear.refraction_error = DioptricPower{};
  EXPECT_TRUE(backend.psf(geometry, options).values == direct.monochromatic(clear, 575.0).values);
  // +3 / -6 x 45: principal powers +3 and -3, mean 0; 3 D over a 5 mm pupil needs dx < 38.3 um,
  // the 128 grid has 78 um: the strongest meridian aliases although the mean power is zero.
  options.phase = PhaseForm::defocus;
  geometry.defocus_dioptres = 0.0;
  geometry.refraction_error = DioptricPower::from_prescription({3.0, -6.0, 45.0});
  (void)backend.psf(geometry, options);
  EXPECT_EQ(backend.last_warning(),
            check_power_error_sampling(geometry.total_power_error(), 575.0, 2.5, 10.0 / 128, 10.0).warning);
  EXPECT_NE(backend.last_warning(), "");
  context_->make_current();  // the suite's context, for the tests after this one
}

}  // namespace
}  // namespace glarelab

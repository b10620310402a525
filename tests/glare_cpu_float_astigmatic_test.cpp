// The float32 CPU PSF (glare/cpu/float_psf.h, glare/cpu/float_glare.h) with an astigmatic
// (sphero-cylindrical) power error: the pupil function and the PSF against a CPU double reference
// built here from glare/refraction/astigmatic_phase.h's apply_power_error_phase and glare/cpu/psf.h's
// shifted_power_spectrum on the same rasterised aperture; the display-scale spectral PSF against the
// double spectral path; the second moments against the geometric blur E (r^2 / 4) E^T; a spherical
// error bit for bit as a defocus; the sampling check on the strongest meridian.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <vector>

#include "glare/eye/aperture_raster.h"
#include "glare/refraction/astigmatic_phase.h"
#include "glare/cpu/float_glare.h"
#include "glare/cpu/float_psf.h"
#include "glare/eye/eye_model.h"
#include "glare/cpu/psf.h"
#include "glare/wave/psf_scale.h"
#include "glare/wave/spectral_psf.h"
#include "psf_agreement.h"

namespace glarelab {
namespace {

using test::Agreement;
using test::compare;

constexpr double kWidthMm = 10.0;

// Oblique axes (TABO 30, 45, 120, 70) and a mixed astigmatism (+1 / -2.5: one principal meridian
// hyperopic, the other myopic).
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

CpuFloatPsfSettings float_settings(int n, double wavelength_nm, int supersampling = 2) {
  CpuFloatPsfSettings settings;
  settings.raster.grid_px = n;
  settings.raster.aperture_width_mm = kWidthMm;
  settings.raster.supersampling = supersampling;
  settings.wavelength_nm = wavelength_nm;
  return settings;
}

// The double reference: the same aperture (glare/eye/aperture_raster.h, which CpuFloatPsf uses bit for bit),
// apply_power_error_phase, FFTW double, normalised to sum 1.
Psf reference_psf(const ApertureGeometry& geometry, int n, double wavelength_nm, int supersampling = 2) {
  ApertureRasterOptions raster;
  raster.grid_px = n;
  raster.aperture_width_mm = kWidthMm;
  raster.supersampling = supersampling;
  const ApertureGrid grid = rasterise_aperture(geometry, raster);
  std::vector<double> power = shifted_power_spectrum(
      apply_power_error_phase(grid, geometry.total_power_error(), wavelength_nm), n, FftPrecision::float64);
  double sum = 0.0;
  for (double p : power) sum += p;
  for (double& p : power) p /= sum;
  Psf psf;
  psf.size_px = n;
  psf.channels = 1;
  psf.degrees_per_pixel = psf_degrees_per_pixel(wavelength_nm, kWidthMm);
  psf.values = std::move(power);
  return psf;
}

struct Moments {
  double xx = 0.0, xy = 0.0, yy = 0.0;
};
// Central second moments in the observer frame (x right, y up; PSF row 0 at the top), rad^2.
Moments second_moments(const Psf& psf) {
  const int n = psf.size_px;
  const double step_rad = psf.degrees_per_pixel * std::numbers::pi / 180.0;
  double mx = 0.0, my = 0.0;
  for (int py = 0; py < n; ++py)
    for (int px = 0; px < n; ++px) mx += psf.at(0, px, py) * (px - n / 2) * step_rad, my += psf.at(0, px, py) * (n / 2 - py) * step_rad;
  Moments m;
  for (int py = 0; py < n; ++py)
    for (int px = 0; px < n; ++px) {
      const double w = psf.at(0, px, py), x = (px - n / 2) * step_rad - mx, y = (n / 2 - py) * step_rad - my;
      m.xx += w * x * x, m.xy += w * x * y, m.yy += w * y * y;
    }
  return m;
}

TEST(GlareCpuFloatAstigmatic, FieldAndPsfMatchTheDoubleReferenceForObliqueAndMixedPrescriptions) {
  const int n = 256;
  const double pupil_mm = 5.0, wavelength_nm = 600.0;
  CpuFloatPsf psf(float_settings(n, wavelength_nm));
  for (const SpheroCylinder& prescription : kPrescriptions) {
    const ApertureGeometry geometry = busy_eye(pupil_mm, prescription);
    ASSERT_TRUE(geometry.astigmatic());
    psf.rasterise(geometry);
    psf.transform(pupil_mm, geometry.total_power_error());
    EXPECT_EQ(psf.sampling_warning(), "");
    const std::vector<std::complex<double>> field =
        apply_power_error_phase(psf.aperture(), geometry.total_power_error(), wavelength_nm);
    double field_error = 0.0;
    for (std::size_t k = 0; k < field.size(); ++k)
      field_error = std::max(field_error, std::abs(std::complex<double>(psf.field()[k]) - field[k]));
    const Agreement agreement = compare(psf.monochromatic_psf().values, reference_psf(geometry, n, wavelength_nm).values);
    std::printf("float32 astigmatic %+.2f / %+.2f x %3.0f: field max error %.2e, PSF max error / peak %.2e, relative L2 %.2e\n",
                prescription.sphere_dioptres, prescription.cylinder_dioptres, prescription.axis_deg, field_error,
                agreement.max_over_peak, agreement.relative_l2);
    // The phase is evaluated in double as the reference does and rounded once to float: half an
    // ulp of the unit amplitude per component.
    EXPECT_LT(field_error, 1e-7);
    EXPECT_LT(agreement.max_over_peak, 1e-5);
    EXPECT_LT(agreement.relative_l2, 1e-5);
  }
}

TEST(GlareCpuFloatAstigmatic, DisplayPsfMatchesTheDoubleSpectralPath) {
  // CpuFloatGlare (the session path) takes the geometry's whole error; against the double path:
  // the astigmatic reference PSF, spectral_psf_from_reference, resample_psf_to_display.
  const int n = 256;
  const EyeModel eye(EyeParameters{}, 1);
  ApertureGeometry geometry = eye.geometry_at(1.2);
  geometry.refraction_error = DioptricPower::from_prescription({-0.25, -1.0, 120.0});
  CpuFloatGlareSettings settings;
  settings.grid_px = n;
  settings.aperture_width_mm = kWidthMm;
  const Psf reference_mono = reference_psf(geometry, n, settings.reference_wavelength_nm);
  settings.display_degrees_per_pixel = 4.0 * reference_mono.degrees_per_pixel;
  CpuFloatGlare glare(settings);
  const Psf display = glare.display_psf(geometry);
  const Psf expected = resample_psf_to_display(spectral_psf_from_reference(reference_mono, SpectralPsfOptions{}).psf,
                                               settings.display_degrees_per_pixel);
  ASSERT_EQ(display.values.size(), expected.values.size());
  const Agreement agreement = compare(display.values, expected.values);
  std::printf("float32 display PSF, eye at 1.2 s with -0.25 / -1.00 x 120: max error / peak %.2e, relative L2 %.2e\n",
              agreement.max_over_peak, agreement.relative_l2);
  EXPECT_LT(agreement.relative_l2, 1e-5);
  // Not the PSF without the refraction: the error is there.
  ApertureGeometry emmetrope = geometry;
  emmetrope.refraction_error = DioptricPower{};
  EXPECT_GT(compare(glare.display_psf(emmetrope).values, expected.values).relative_l2, 1e-2);
}

TEST(GlareCpuFloatAstigmatic, SecondMomentsAreThePupilMappedByThePowerError) {
  // Geometric optics: the ray through pupil point p leaves at angle E p, so the PSF is the pupil
  // disc mapped by E, covariance E (r^2 / 4 I) E^T for a uniform disc of radius r. Diffraction adds
  // a term that is isotropic for a round pupil, so xy and xx - yy are the geometric ones. Dropping
  // the cross term would give E' = diag(E_xx, E_yy) and xy = 0.
  const int n = 512;
  const double pupil_mm = 4.0, wavelength_nm = 575.0, r_m = 0.5 * pupil_mm * 1e-3;
  CpuFloatPsf psf(float_settings(n, wavelength_nm, 4));
  for (const SpheroCylinder& prescription :
       {SpheroCylinder{0.0, -2.0, 45.0}, SpheroCylinder{-1.0, -1.5, 30.0}, SpheroCylinder{1.0, -2.5, 120.0}}) {
    ApertureGeometry geometry;
    geometry.pupil_diameter_mm = pupil_mm;
    geometry.refraction_error = DioptricPower::from_prescription(prescription);
    psf.rasterise(geometry);
    psf.transform(pupil_mm, geometry.total_power_error());
    const glm::dmat2 e = geometry.total_power_error().matrix_dioptres;
    const glm::dmat2 predicted = e * (0.25 * r_m * r_m) * glm::transpose(e);
    const Moments measured = second_moments(psf.monochromatic_psf());
    const double scale = 0.25 * r_m * r_m * (e[0][0] * e[0][0] + 2.0 * e[1][0] * e[1][0] + e[1][1] * e[1][1]);
    std::printf("float32 moments %+.2f / %+.2f x %3.0f: xy %.4e (predicted %.4e), xx - yy %.4e (predicted %.4e) rad^2\n",
                prescription.sphere_dioptres, prescription.cylinder_dioptres, prescription.axis_deg, measured.xy,
                predicted[1][0], measured.xx - measured.yy, predicted[0][0] - predicted[1][1]);
    ASSERT_GT(std::abs(predicted[1][0]), 0.1 * scale);  // the cross term matters here
    EXPECT_NEAR(measured.xy, predicted[1][0], 0.02 * scale);
    EXPECT_NEAR(measured.xx - measured.yy, predicted[0][0] - predicted[1][1], 0.02 * scale);
  }
}

TEST(GlareCpuFloatAstigmatic, SphericalErrorsAreTheDefocusPathBitForBit) {
  const int n = 128;
  ApertureGeometry with_refraction = busy_eye(5.0, {});
  with_refraction.defocus_dioptres = 0.5;
  with_refraction.refraction_error = DioptricPower::spherical(0.25);
  ASSERT_FALSE(with_refraction.astigmatic());
  ApertureGeometry defocus_only = with_refraction;
  defocus_only.refraction_error = DioptricPower{};
  defocus_only.defocus_dioptres = 0.75;
  // CpuFloatPsf: the error overload with a spherical error is the scalar defocus path.
  CpuFloatPsf a(float_settings(n, 575.0)), b(float_settings(n, 575.0));
  a.rasterise(with_refraction);
  a.transform(5.0, with_refraction.total_power_error());
  b.rasterise(defocus_only);
  b.transform(5.0, defocus_only.defocus_dioptres);
  EXPECT_TRUE(std::equal(a.power_column_major(), a.power_column_major() + n * n, b.power_column_major()));
  // CpuFloatGlare: the session path, whole display PSF.
  CpuFloatGlareSettings settings;
  settings.grid_px = n;
  settings.wavelength_samples = 8;
  settings.display_degrees_per_pixel = 4.0 * psf_degrees_per_pixel(575.0, settings.aperture_width_mm);
  CpuFloatGlare glare_a(settings), glare_b(settings);
  EXPECT_TRUE(glare_a.display_psf(with_refraction).values == glare_b.display_psf(defocus_only).values);
}

TEST(GlareCpuFloatAstigmatic, SamplingIsCheckedOnTheStrongestMeridian) {
  // +3 / -6 x 45: principal powers +3 and -3, mean 0. 3 D over a 5 mm pupil needs dx < 38.3 um at
  // 575 nm; the 128 grid over 10 mm has 78 um: aliased, although a defocus of the mean would not be.
  const int n = 128;
  ApertureGeometry geometry = busy_eye(5.0, {3.0, -6.0, 45.0});
  geometry.defocus_dioptres = 0.0;
  CpuFloatGlareSettings settings;
  settings.grid_px = n;
  settings.wavelength_samples = 8;
  settings.display_degrees_per_pixel = 4.0 * psf_degrees_per_pixel(575.0, settings.aperture_width_mm);
  CpuFloatGlare glare(settings);
  (void)glare.display_psf(geometry);
  EXPECT_EQ(glare.sampling_warning(),
            check_power_error_sampling(geometry.total_power_error(), 575.0, 2.5, kWidthMm / n, kWidthMm).warning);
  EXPECT_NE(glare.sampling_warning(), "");
  geometry.refraction_error = DioptricPower::from_prescription({0.25, -0.5, 45.0});
  (void)glare.display_psf(geometry);
  EXPECT_EQ(glare.sampling_warning(), "");
}

}  // namespace
}  // namespace glarelab

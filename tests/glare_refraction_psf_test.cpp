// The wave-optics PSF of an eye with a refraction (glare/cpu/psf.h with ApertureGeometry's
// refraction_error): its second moments against the geometric blur of the residual error, the
// Sturm-conoid ellipse, for defocus and for astigmatism at regular and oblique axes.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <glm/mat2x2.hpp>

#include "glare/refraction/eye_refraction.h"
#include "glare/cpu/psf.h"
#include "glare_refraction_test_support.h"

namespace glarelab {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// 4 mm pupil on 8 mm (twice the pupil: the intensity is sampled without aliasing), 512 px: PSF pixels
// of 575 nm / 8 mm = 0.0041 deg, phase sampled up to 9.2 D at the pupil edge.
MonochromaticPsfOptions psf_options() {
  MonochromaticPsfOptions options;
  options.raster.grid_px = 512;
  options.raster.aperture_width_mm = 8.0;
  options.wavelength_nm = 575.0;
  options.strict_sampling = true;
  return options;
}

ApertureGeometry eye_with(const DioptricPower& residual) {
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 4.0;
  geometry.refraction_error = residual;
  return geometry;
}

TEST(GlareRefractionPsf, PresbyopeBlurDiscMomentsMatchTheGeometricDisc) {
  // 1 D of amplitude at 0.25 m leaves -3 D: a disc of radius R = 3 D * 2 mm = 6 mrad (0.344 deg),
  // <x^2> = <y^2> = R^2 / 4.
  EyeRefraction presbyope;
  presbyope.accommodation_amplitude_dioptres = 1.0;
  const FixationRefraction reading = refraction_at_fixation(RefractiveEye(presbyope), {0.25, std::nullopt});
  const MonochromaticPsfResult result = compute_monochromatic_psf(eye_with(reading.residual), psf_options());
  ASSERT_TRUE(result.sampling_warning.empty()) << result.sampling_warning;
  const double radius_deg = 6e-3 * kDegPerRad;
  const test::PsfMoments moments = test::psf_moments(result.psf, 0);
  const double expected = radius_deg * radius_deg / 4.0;
  std::cout << "presbyope 3 D, 4 mm: <x^2> " << moments.xx_deg2 << ", <y^2> " << moments.yy_deg2
            << " deg^2, geometric R^2/4 " << expected << " (R = " << radius_deg << " deg)\n";
  EXPECT_NEAR(moments.xx_deg2 / expected, 1.0, 0.10);
  EXPECT_NEAR(moments.yy_deg2 / expected, 1.0, 0.10);
  EXPECT_NEAR(moments.xy_deg2 / expected, 0.0, 0.01);
  // Most of the 2.6 % excess is the in-focus PSF's own (edge diffraction) moment, which adds
  // (|grad(A exp(i phi))|^2 = |grad A|^2 + A^2 |grad phi|^2): without it the disc agrees to 1 %.
  ApertureGeometry in_focus;
  in_focus.pupil_diameter_mm = 4.0;
  const test::PsfMoments diffraction = test::psf_moments(compute_monochromatic_psf(in_focus, psf_options()).psf, 0);
  EXPECT_NEAR((moments.xx_deg2 - diffraction.xx_deg2) / expected, 1.0, 0.01);
}

TEST(GlareRefractionPsf, AstigmaticPsfIsTheSturmConoidEllipse) {
  // No accommodation, so the residual is -K, the prescription's own power at the cornea. The ray
  // through pupil point p leaves at E p, so the geometric second-moment matrix is E <p p^T> E =
  // (r^2 / 4) E^2: axes from E's principal powers, orientation from its principal directions. The
  // wave PSF adds the in-focus PSF's moments (|grad(A exp(i phi))|^2 = |grad A|^2 + A^2 |grad phi|^2
  // for a real pupil A), measured here on the same grid and removed before the comparison.
  const MonochromaticPsfResult focus = compute_monochromatic_psf(eye_with(DioptricPower{}), psf_options());
  const test::PsfMoments diffraction = test::psf_moments(focus.psf, 0);
  std::cout << "in focus, 4 mm, 575 nm: <x^2> " << diffraction.xx_deg2 << " deg^2 (edge diffraction)\n";
  for (const SpheroCylinder rx : {SpheroCylinder{0.0, -3.0, 45.0}, SpheroCylinder{-1.0, -2.0, 30.0},
                                  SpheroCylinder{-2.0, -1.5, 120.0}, SpheroCylinder{-1.5, -2.0, 90.0},
                                  SpheroCylinder{-0.5, -2.5, 0.0}, SpheroCylinder{1.0, -3.0, 160.0}}) {
    EyeRefraction refraction;
    refraction.correcting_prescription = rx;
    refraction.accommodation_amplitude_dioptres = 0.0;
    const RefractiveEye eye(refraction);
    const DioptricPower residual = refraction_at_fixation(eye, {}).residual;
    const ApertureGeometry geometry = eye_with(residual);
    ASSERT_TRUE(geometry.astigmatic());
    const MonochromaticPsfResult result = compute_monochromatic_psf(geometry, psf_options());
    ASSERT_TRUE(result.sampling_warning.empty()) << result.sampling_warning;
    test::PsfMoments moments = test::psf_moments(result.psf, 0);
    // Closed form: (r^2 / 4) E^2 in deg^2.
    const glm::dmat2 e2 = residual.matrix_dioptres * residual.matrix_dioptres * (1e-6 * kDegPerRad * kDegPerRad);
    const double xx = moments.xx_deg2 - diffraction.xx_deg2, yy = moments.yy_deg2 - diffraction.yy_deg2,
                 xy = moments.xy_deg2 - diffraction.xy_deg2;
    const BlurEllipse blur = geometric_blur_ellipse(residual, 2e-3);
    const double major_deg = blur.semi_major_rad * kDegPerRad, minor_deg = blur.semi_minor_rad * kDegPerRad;
    const double scale = major_deg * major_deg / 4.0;  // the largest eigenvalue
    EXPECT_NEAR(xx / scale, e2[0][0] / scale, 0.03) << rx.axis_deg;
    EXPECT_NEAR(xy / scale, e2[1][0] / scale, 0.03) << rx.axis_deg;
    EXPECT_NEAR(yy / scale, e2[1][1] / scale, 0.03) << rx.axis_deg;
    const double half_difference = 0.5 * (xx - yy), radius = std::hypot(half_difference, xy), mean = 0.5 * (xx + yy);
    const double semi_major = 2.0 * std::sqrt(mean + radius), semi_minor = 2.0 * std::sqrt(std::max(0.0, mean - radius));
    double angle = 0.5 * std::atan2(xy, half_difference) * kDegPerRad;
    if (angle < 0.0) angle += 180.0;
    std::cout << rx.sphere_dioptres << " / " << rx.cylinder_dioptres << " x " << rx.axis_deg << ": semi-axes "
              << semi_major << " x " << semi_minor << " deg at " << angle << " deg (raw " << moments.semi_major_deg
              << " x " << moments.semi_minor_deg << "); geometric " << major_deg << " x " << minor_deg << " deg at "
              << blur.major_axis_angle_deg << "\n";
    EXPECT_NEAR(semi_major / major_deg, 1.0, 0.02) << rx.axis_deg;
    // A line focus' minor axis is the square root of a small difference: 0.011 deg for 0 / -3 x 45.
    EXPECT_NEAR(semi_minor, minor_deg, 0.04 * major_deg) << rx.axis_deg;
    EXPECT_LT(test::axis_difference_deg(angle, blur.major_axis_angle_deg), 0.5) << rx.axis_deg;
    // Without removing the diffraction term the major axis is still within 5 %.
    EXPECT_NEAR(moments.semi_major_deg / major_deg, 1.0, 0.05) << rx.axis_deg;
    EXPECT_LT(test::axis_difference_deg(moments.major_angle_deg, blur.major_axis_angle_deg), 1.0) << rx.axis_deg;
  }
}

TEST(GlareRefractionPsf, TaboAxisSetsTheImageOrientation) {
  // A plain minus cylinder -3 x TABO 45 uncorrected: K = -3 D across the axis. The TABO 45 axis runs
  // up and to the observer's left (observer 135 deg), so the eye is too strong along 45 deg (up and
  // to the observer's right): the PSF is a streak from the lower left to the upper right of the
  // image as the observer sees it, i.e. toward column > N/2 at row < N/2.
  EyeRefraction refraction;
  refraction.correcting_prescription = {0.0, -3.0, 45.0};
  refraction.prescription_vertex_distance_m = 0.0;
  const DioptricPower residual = refraction_at_fixation(RefractiveEye(refraction), {}).residual;
  const Psf psf = compute_monochromatic_psf(eye_with(residual), psf_options()).psf;
  const int c = psf.size_px / 2, k = 40;  // 40 px diagonally = 0.23 deg, inside the 0.34 deg streak
  EXPECT_GT(psf.at(0, c + k, c - k), 20.0 * psf.at(0, c - k, c - k));
  EXPECT_GT(psf.at(0, c - k, c + k), 20.0 * psf.at(0, c + k, c + k));
}

TEST(GlareRefractionPsf, OwnSpectaclesMakeItSharpAgain) {
  for (const SpheroCylinder rx : {SpheroCylinder{-3.0, -1.5, 30.0}, SpheroCylinder{2.0, -2.0, 120.0}}) {
    EyeRefraction refraction;
    refraction.correcting_prescription = rx;
    const RefractiveEye eye(refraction);
    const ThinSpectacleLens lens{rx, refraction.prescription_vertex_distance_m};
    const Psf blurred = compute_monochromatic_psf(eye_with(refraction_at_fixation(eye, {}).residual), psf_options()).psf;
    const Psf corrected = compute_monochromatic_psf(
        eye_with(refraction_at_fixation(eye, {std::numeric_limits<double>::infinity(), lens}).residual), psf_options()).psf;
    const double sharp = test::encircled_fraction(corrected, 0, 0.05);
    const double blur = test::encircled_fraction(blurred, 0, 0.05);
    std::cout << rx.sphere_dioptres << " / " << rx.cylinder_dioptres << " x " << rx.axis_deg
              << ": light within 0.05 deg " << blur << " uncorrected, " << sharp << " with its spectacles\n";
    EXPECT_GT(sharp, 0.9);
    EXPECT_LT(blur, 0.2);
  }
}

TEST(GlareRefractionPsf, NoRefractionKeepsTheDefocusPathBitForBit) {
  ApertureGeometry plain;
  plain.pupil_diameter_mm = 4.0;
  plain.defocus_dioptres = 1.25;
  MonochromaticPsfOptions options = psf_options();
  options.raster.grid_px = 128;
  const Psf expected = compute_monochromatic_psf(rasterise_aperture(plain, options.raster), 4.0, 1.25, options).psf;
  EXPECT_EQ(compute_monochromatic_psf(plain, options).psf.values, expected.values);
  // A spherical refraction error is the same phase as a defocus: exactly the same PSF.
  ApertureGeometry spherical;
  spherical.pupil_diameter_mm = 4.0;
  spherical.refraction_error = DioptricPower::spherical(1.25);
  EXPECT_FALSE(spherical.astigmatic());
  EXPECT_EQ(compute_monochromatic_psf(spherical, options).psf.values, expected.values);
}

TEST(GlareRefractionPsf, AstigmaticPhaseIsCheckedForSampling) {
  // 30 D along one meridian on 512 px over 8 mm (max 9.2 D at the 4 mm pupil's edge): aliased.
  ApertureGeometry geometry = eye_with(DioptricPower::from_prescription({0.0, 30.0, 20.0}));
  MonochromaticPsfOptions options = psf_options();
  EXPECT_THROW(compute_monochromatic_psf(geometry, options), std::runtime_error);
  options.strict_sampling = false;
  EXPECT_NE(compute_monochromatic_psf(geometry, options).sampling_warning.find("aliased"), std::string::npos);
  options.phase = PhaseForm::paper;
  EXPECT_THROW(compute_monochromatic_psf(geometry, options), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab

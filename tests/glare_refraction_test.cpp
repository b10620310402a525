// The observer's refraction (glare/refraction/eye_refraction.h): Kakimoto et al. 2007, Eqs. 8-15 and Table 2,
// against hand-worked vergences and the paper's own Sturm-conoid section.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "glare/refraction/eye_refraction.h"

namespace glarelab {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kDegPerRad = 180.0 / std::numbers::pi;

void expect_power(const DioptricPower& power, double xx, double xy, double yy, double tolerance = 1e-12) {
  EXPECT_NEAR(power.xx(), xx, tolerance);
  EXPECT_NEAR(power.xy(), xy, tolerance);
  EXPECT_NEAR(power.yy(), yy, tolerance);
}

EyeRefraction prescription(double sphere, double cylinder, double axis_deg, double amplitude = 11.93) {
  EyeRefraction refraction;
  refraction.correcting_prescription = {sphere, cylinder, axis_deg};
  refraction.accommodation_amplitude_dioptres = amplitude;
  return refraction;
}

TEST(GlareRefraction, SchematicEyeIsTable2) {
  // n2 / z_r = 1.336 / 0.022785 m = 58.6350 D; Table 2 rounds it to 58.64.
  EXPECT_NEAR(emmetropic_power_dioptres(), 58.63506, 1e-5);
  EXPECT_NEAR(emmetropic_power_dioptres(), kSchematicRelaxedPowerDioptres, 0.005);
  const RefractiveEye emmetrope(EyeRefraction{});
  EXPECT_NEAR(emmetrope.relaxed_principal_powers().mean_dioptres, 58.635, 1e-3);
  EXPECT_EQ(emmetrope.refraction().accommodation_amplitude_dioptres, 11.93);
}

TEST(GlareRefraction, EmmetropeAtInfinityHasNoResidualAndAccommodatesForNearPoints) {
  const RefractiveEye emmetrope(EyeRefraction{});
  const FixationRefraction far = refraction_at_fixation(emmetrope, {});
  EXPECT_EQ(far.accommodation_dioptres, 0.0);
  expect_power(far.residual, 0.0, 0.0, 0.0, 1e-12);
  // Eq. 13: a point at 0.5 m reaches the cornea with -2 D; the eye adds 2 D and is sharp again.
  const FixationRefraction near = refraction_at_fixation(emmetrope, {0.5, std::nullopt});
  EXPECT_NEAR(near.accommodation_dioptres, 2.0, 1e-12);
  expect_power(near.residual, 0.0, 0.0, 0.0, 1e-12);
}

TEST(GlareRefraction, PresbopeWithOneDioptreKeepsThreeAtAQuarterMetre) {
  const RefractiveEye presbyope(prescription(0, 0, 0, 1.0));
  const FixationRefraction reading = refraction_at_fixation(presbyope, {0.25, std::nullopt});
  EXPECT_NEAR(reading.accommodation_dioptres, 1.0, 1e-12);  // clamped at the amplitude
  expect_power(reading.residual, -3.0, 0.0, -3.0, 1e-12);   // too little power: hyperopic blur
  // 4 mm pupil: a disc of radius 3 D * 2 mm = 6 mrad, 0.6875 degrees across.
  const BlurEllipse blur = geometric_blur_ellipse(reading.residual, 2e-3);
  EXPECT_NEAR(2.0 * blur.semi_major_rad * kDegPerRad, 0.6875, 5e-4);
  EXPECT_NEAR(blur.semi_minor_rad, blur.semi_major_rad, 1e-15);
}

TEST(GlareRefraction, HofstetterAmplitude) {
  // 18.5 - 0.3 age (Hofstetter 1950), floored at 0.
  EXPECT_NEAR(hofstetter_amplitude_dioptres(25.0), 11.0, 1e-12);
  EXPECT_NEAR(hofstetter_amplitude_dioptres(40.0), 6.5, 1e-12);
  EXPECT_NEAR(hofstetter_amplitude_dioptres(60.0), 0.5, 1e-12);
  EXPECT_EQ(hofstetter_amplitude_dioptres(70.0), 0.0);
  EXPECT_THROW(hofstetter_amplitude_dioptres(-1.0), std::invalid_argument);
}

TEST(GlareRefraction, MyopeSpectaclePrescriptionMovesToTheCornea) {
  // -4 D at 12 mm: K = -4 / (1 + 0.012 * 4) = -3.81679 D at the cornea; the relaxed eye is that much
  // too strong (Table 3: refractive myopia, P-bar_min > 58.64).
  const RefractiveEye myope(prescription(-4.0, 0.0, 0.0));
  const double k = -4.0 / 1.048;
  expect_power(myope.ocular_refraction(), k, 0.0, k, 1e-12);
  EXPECT_NEAR(myope.relaxed_principal_powers().mean_dioptres, emmetropic_power_dioptres() - k, 1e-12);
  expect_power(refraction_at_fixation(myope, {}).residual, -k, 0.0, -k, 1e-12);  // +3.82 D too strong
  // A point at 0.5 m: -2 D at the naked cornea, less than |K|: no accommodation, 1.82 D left.
  const FixationRefraction near = refraction_at_fixation(myope, {0.5, std::nullopt});
  EXPECT_EQ(near.accommodation_dioptres, 0.0);
  expect_power(near.residual, -2.0 - k, 0.0, -2.0 - k, 1e-12);
}

TEST(GlareRefraction, OwnSpectaclesCorrectAtEveryFixationDistance) {
  const EyeRefraction refraction = prescription(-3.0, -1.5, 30.0);
  const RefractiveEye eye(refraction);
  const ThinSpectacleLens lens{refraction.correcting_prescription, refraction.prescription_vertex_distance_m};
  const FixationRefraction far = refraction_at_fixation(eye, {kInfinity, lens});
  EXPECT_EQ(far.accommodation_dioptres, 0.0);
  expect_power(far.residual, 0.0, 0.0, 0.0, 1e-12);
  // At 0.5 m through the lens: the spherical meridian, hand-worked: -1 / 0.488 m - 3 D at the lens,
  // carried 12 mm: L / (1 - 0.012 L); the eye accommodates by mean(K) - mean(V) and is sharp.
  const FixationRefraction near = refraction_at_fixation(eye, {0.5, lens});
  const double at_lens = -1.0 / 0.488 - 3.0;
  const double at_cornea = at_lens / (1.0 - 0.012 * at_lens);
  EXPECT_NEAR(near.fixation_vergence.meridian_dioptres(observer_axis_deg_from_tabo(30.0)), at_cornea, 1e-12);
  EXPECT_NEAR(near.accommodation_dioptres,
              eye.ocular_refraction().mean_dioptres() - near.fixation_vergence.mean_dioptres(), 1e-12);
  // Not quite zero: per principal meridian the lens' vergence at the cornea, (f - s) / (1 - v (f - s)),
  // and K's, f / (1 - v f), differ by an amount that depends on f (s = 1 / 0.488 m, v = 12 mm), so the
  // two meridians need 1.865 and 1.802 D of accommodation; the eye takes their mean and leaves half
  // the 0.062 D difference in each, the spectacle's astigmatic error at near.
  const double s = 1.0 / 0.488, v = 0.012;
  auto extra = [&](double f) { return (f - s) / (1.0 - v * (f - s)) - f / (1.0 - v * f); };
  const double half_difference = 0.5 * std::abs(extra(-3.0) - extra(-4.5));
  EXPECT_NEAR(half_difference, 0.0312, 1e-4);
  const PrincipalPowers left = principal_powers(near.residual);
  EXPECT_NEAR(left.p1_dioptres, half_difference, 1e-12);
  EXPECT_NEAR(left.p2_dioptres, -half_difference, 1e-12);
}

TEST(GlareRefraction, AstigmatismSplitsAboutTheMeanPower) {
  // Eq. 14: -1 / -2 x 30 at the cornea (vertex 0): K is -1 along the axis, -3 across it. The relaxed
  // eye P = n2 / z_r - K is strongest across the axis: A = 2 D, P_1 along the normal to the axis,
  // which (TABO 30 = observer 150 degrees) is at 60 degrees.
  EyeRefraction refraction = prescription(-1.0, -2.0, 30.0);
  refraction.prescription_vertex_distance_m = 0.0;
  const RefractiveEye eye(refraction);
  const EyePrincipalPowers relaxed = eye.relaxed_principal_powers();
  EXPECT_NEAR(relaxed.astigmatism_dioptres, 2.0, 1e-12);
  EXPECT_NEAR(relaxed.mean_dioptres, emmetropic_power_dioptres() + 2.0, 1e-12);
  EXPECT_NEAR(relaxed.p1_min_dioptres, relaxed.mean_dioptres + 1.0, 1e-12);
  EXPECT_NEAR(relaxed.p1_direction_deg, 60.0, 1e-9);
  // At 0.25 m the eye accommodates 4 - 2 = 2 D: the circle of least confusion lies on the retina
  // (Eq. 10, a = -b): the residual is +-A/2 about zero.
  const FixationRefraction reading = refraction_at_fixation(eye, {0.25, std::nullopt});
  EXPECT_NEAR(reading.accommodation_dioptres, 2.0, 1e-12);
  const PrincipalPowers residual = principal_powers(reading.residual);
  EXPECT_NEAR(residual.p1_dioptres, 1.0, 1e-12);
  EXPECT_NEAR(residual.p2_dioptres, -1.0, 1e-12);
  EXPECT_NEAR(residual.principal_angle_deg, 60.0, 1e-9);
  const SturmSection section = sturm_conoid_section(eye, reading.fixation_vergence, reading.accommodation_dioptres, 2e-3);
  EXPECT_NEAR(section.a_m, -section.b_m, 1e-15);
}

TEST(GlareRefraction, DepthOfFieldKeepsTheFixationAccommodation) {
  // Fixating 0.5 m (2 D of accommodation), a point at 2 m reaches the cornea with -0.5 D: 1.5 D too
  // much power; a point at 0.25 m, 2 D too little.
  const RefractiveEye emmetrope(EyeRefraction{});
  const ViewingCondition viewing{0.5, std::nullopt};
  expect_power(residual_error_at(emmetrope, viewing, 2.0), 1.5, 0.0, 1.5, 1e-12);
  expect_power(residual_error_at(emmetrope, viewing, 0.25), -2.0, 0.0, -2.0, 1e-12);
}

TEST(GlareRefraction, SturmConoidSectionIsTheGeometricBlurSeenFromTheNodalPoint) {
  // Eq. 8 gives a, b on the retina, z_r behind the thin lens in the vitreous (n2). Seen from the
  // nodal point (z_r / n2 in front of the retina, 17.05 mm) they are the angles |E_i| r_p of
  // geometric_blur_ellipse exactly; divided by z_r alone (the angle inside the eye) they are smaller
  // by the factor n2 = 1.336, 25.1 % less.
  for (const SpheroCylinder rx : {SpheroCylinder{-2.0, -1.0, 30.0}, SpheroCylinder{1.5, -2.5, 120.0},
                                  SpheroCylinder{0.0, -3.0, 45.0}, SpheroCylinder{-5.0, 0.0, 0.0}}) {
    EyeRefraction refraction;
    refraction.correcting_prescription = rx;
    refraction.accommodation_amplitude_dioptres = 0.5;
    const RefractiveEye eye(refraction);
    for (double distance_m : {kInfinity, 1.0, 0.3}) {
      const FixationRefraction fixation = refraction_at_fixation(eye, {distance_m, std::nullopt});
      const double pupil_radius_m = 2e-3;
      const SturmSection section =
          sturm_conoid_section(eye, fixation.fixation_vergence, fixation.accommodation_dioptres, pupil_radius_m);
      const PrincipalPowers residual = principal_powers(fixation.residual);
      // a = r_p (1 - kappa'_1 z_r) with kappa'_1 = (n2 / z_r + E_1) / n2, i.e. -r_p E_1 z_r / n2.
      const double nodal_m = kSchematicCorneaRetina_m / kVitreousIndex;
      EXPECT_NEAR(section.a_m / nodal_m, -pupil_radius_m * residual.p1_dioptres, 1e-12);
      EXPECT_NEAR(section.b_m / nodal_m, -pupil_radius_m * residual.p2_dioptres, 1e-12);
      const BlurEllipse blur = geometric_blur_ellipse(fixation.residual, pupil_radius_m);
      EXPECT_NEAR(std::max(std::abs(section.a_m), std::abs(section.b_m)) / nodal_m, blur.semi_major_rad, 1e-12);
      if (residual.p1_dioptres != residual.p2_dioptres) {
        EXPECT_NEAR(section.first_direction_deg, residual.principal_angle_deg, 1e-9);
      }
      if (blur.semi_major_rad > 1e-6) {
        const double inside_eye_rad = std::max(std::abs(section.a_m), std::abs(section.b_m)) / kSchematicCorneaRetina_m;
        EXPECT_NEAR(inside_eye_rad / blur.semi_major_rad, 1.0 / kVitreousIndex, 1e-9);
        EXPECT_NEAR(1.0 - inside_eye_rad / blur.semi_major_rad, 0.2515, 1e-4);
      }
    }
  }
}

TEST(GlareRefraction, RefusesWhatItCannotModel) {
  EXPECT_THROW(RefractiveEye(prescription(0, 0, 0, -1.0)), std::invalid_argument);
  EXPECT_THROW(vergence_at_cornea(0.01, ThinSpectacleLens{{-2.0, 0.0, 0.0}, 0.012}), std::invalid_argument);
  EXPECT_THROW(vergence_at_cornea(0.0, std::nullopt), std::invalid_argument);
  // A +83.3 D lens at 12 mm focuses at the cornea: no finite ocular refraction.
  EyeRefraction focusing = prescription(1.0 / 0.012, 0.0, 0.0);
  EXPECT_THROW(RefractiveEye{focusing}, std::invalid_argument);
}

}  // namespace
}  // namespace glarelab

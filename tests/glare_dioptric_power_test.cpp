// Dioptric power matrices against hand-worked prescriptions (glare/refraction/dioptric_power.h).
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "glare/refraction/dioptric_power.h"

namespace glarelab {
namespace {

TEST(DioptricPower, VerticalAxisPutsSphereInTheVerticalMeridianAndSpherePlusCylinderAcross) {
  // -2.00 / -1.00 x 90: the vertical meridian (along the axis) has -2 D, the horizontal -3 D.
  const DioptricPower power = DioptricPower::from_prescription({-2.0, -1.0, 90.0});
  EXPECT_NEAR(power.xx(), -3.0, 1e-12);
  EXPECT_NEAR(power.yy(), -2.0, 1e-12);
  EXPECT_NEAR(power.xy(), 0.0, 1e-12);
  EXPECT_NEAR(power.meridian_dioptres(90.0), -2.0, 1e-12);
  EXPECT_NEAR(power.meridian_dioptres(0.0), -3.0, 1e-12);
  EXPECT_NEAR(power.mean_dioptres(), -2.5, 1e-12);
}

TEST(DioptricPower, TaboAxisIsMirroredIntoTheObserversFrame) {
  // TABO 45 runs up and to the examiner's right = the observer's left: 135 deg in the observer frame.
  EXPECT_NEAR(observer_axis_deg_from_tabo(45.0), 135.0, 1e-12);
  EXPECT_NEAR(observer_axis_deg_from_tabo(0.0), 0.0, 1e-12);
  EXPECT_NEAR(observer_axis_deg_from_tabo(90.0), 90.0, 1e-12);
  EXPECT_NEAR(tabo_from_observer_axis_deg(135.0), 45.0, 1e-12);
  // Plano / -2 x 45: the axis meridian (observer 135 deg) has 0 D, the meridian at 45 deg has -2 D.
  const DioptricPower power = DioptricPower::from_prescription({0.0, -2.0, 45.0});
  EXPECT_NEAR(power.meridian_dioptres(135.0), 0.0, 1e-12);
  EXPECT_NEAR(power.meridian_dioptres(45.0), -2.0, 1e-12);
  // Hand-worked: n = (-sin 135, cos 135) = (-0.7071, -0.7071), C n n^T = -2 * 0.5 [[1, 1], [1, 1]].
  EXPECT_NEAR(power.xx(), -1.0, 1e-12);
  EXPECT_NEAR(power.xy(), -1.0, 1e-12);
  EXPECT_NEAR(power.yy(), -1.0, 1e-12);
}

TEST(DioptricPower, PrescriptionRoundTripsAndPlusCylinderTransposes) {
  for (double axis : {0.0, 17.0, 45.0, 90.0, 133.0, 179.0}) {
    const SpheroCylinder written{+1.25, -0.75, axis};
    const SpheroCylinder back = DioptricPower::from_prescription(written).prescription();
    EXPECT_NEAR(back.sphere_dioptres, 1.25, 1e-12) << axis;
    EXPECT_NEAR(back.cylinder_dioptres, -0.75, 1e-12) << axis;
    EXPECT_NEAR(back.axis_deg, axis, 1e-9) << axis;
    // +0.50 / +0.75 x (axis + 90) is the same lens as +1.25 / -0.75 x axis.
    const SpheroCylinder plus{0.5, 0.75, std::fmod(axis + 90.0, 180.0)};
    const DioptricPower difference = DioptricPower::from_prescription(plus) - DioptricPower::from_prescription(written);
    EXPECT_NEAR(difference.xx(), 0.0, 1e-12);
    EXPECT_NEAR(difference.xy(), 0.0, 1e-12);
    EXPECT_NEAR(difference.yy(), 0.0, 1e-12);
  }
}

TEST(DioptricPower, VertexDistanceCompensationMatchesTheSphericalFormula) {
  // A +10 D lens 12 mm in front of the cornea acts there as 10 / (1 - 0.012 * 10) = 11.364 D.
  const DioptricPower moved = effective_power_at_distance(DioptricPower::spherical(10.0), 0.012);
  EXPECT_NEAR(moved.xx(), 10.0 / (1.0 - 0.12), 1e-12);
  EXPECT_NEAR(moved.yy(), 10.0 / (1.0 - 0.12), 1e-12);
  // A sphero-cylinder: each principal meridian moves by the spherical formula, axes unchanged.
  const DioptricPower lens = DioptricPower::from_prescription({-4.0, -2.0, 30.0});
  const PrincipalPowers principal = principal_powers(effective_power_at_distance(lens, 0.014));
  EXPECT_NEAR(principal.p1_dioptres, -4.0 / (1.0 + 0.014 * 4.0), 1e-12);
  EXPECT_NEAR(principal.p2_dioptres, -6.0 / (1.0 + 0.014 * 6.0), 1e-12);
  EXPECT_NEAR(principal.principal_angle_deg, observer_axis_deg_from_tabo(30.0), 1e-9);
  EXPECT_THROW(effective_power_at_distance(DioptricPower::spherical(50.0), 0.02), std::invalid_argument);
}

TEST(DioptricPower, BlurEllipseIsThePupilMappedByTheError) {
  // 3 D of defocus over a 4 mm pupil: a disc 3 * 0.004 rad = 0.6875 deg across (the closed form's number).
  const BlurEllipse disc = geometric_blur_ellipse(DioptricPower::spherical(3.0), 0.002);
  EXPECT_NEAR(2.0 * disc.semi_major_rad * 180.0 / 3.14159265358979323846, 0.6875, 1e-3);
  EXPECT_DOUBLE_EQ(disc.semi_major_rad, disc.semi_minor_rad);
  // Mixed astigmatism +1 / -2 x 45 over a 6 mm pupil: meridian powers +1 (observer 135) and -1 (45).
  const BlurEllipse ellipse = geometric_blur_ellipse(DioptricPower::from_prescription({1.0, -2.0, 45.0}), 0.003);
  EXPECT_NEAR(ellipse.semi_major_rad, 0.003, 1e-15);
  EXPECT_NEAR(ellipse.semi_minor_rad, 0.003, 1e-15);
  // Simple astigmatism 0 / -2 x 60: a line along the meridian with power, observer 120 + 90 = 30 deg.
  const BlurEllipse line = geometric_blur_ellipse(DioptricPower::from_prescription({0.0, -2.0, 60.0}), 0.002);
  EXPECT_NEAR(line.semi_major_rad, 0.004, 1e-15);
  EXPECT_NEAR(line.semi_minor_rad, 0.0, 1e-15);
  EXPECT_NEAR(line.major_axis_angle_deg, 30.0, 1e-9);
}

}  // namespace
}  // namespace glarelab

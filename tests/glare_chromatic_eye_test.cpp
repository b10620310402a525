// Longitudinal chromatic aberration (glare/refraction/chromatic_eye.h): Thibos et al. 1992's fit against the
// same paper's reduced eye (its water-like index and 5.55 mm corneal radius), and hand-worked values.
#include <gtest/gtest.h>

#include <stdexcept>

#include "glare/refraction/chromatic_eye.h"

namespace glarelab {
namespace {

// Thibos et al. 1992, p. 3596: the chromatic eye's index n(lambda) = a + b / (lambda - c) (lambda in
// um), corneal radius r = 5.55 mm, n_D = 1.333; the refraction it needs, (n_D - n(lambda)) / (n_D r).
double reduced_eye_refraction_dioptres(double wavelength_nm) {
  const double a = 1.320535, b = 0.004685, c = 0.214102, radius_m = 5.55e-3, n_d = 1.333;
  const double index = a + b / (wavelength_nm * 1e-3 - c);
  return (n_d - index) / (n_d * radius_m);
}

TEST(GlareChromaticEye, FormulaValuesAndZero) {
  // Rx = 1.68524 - 0.63346 / (lambda - 0.21410): hand-worked at 400 and 700 nm.
  EXPECT_NEAR(chromatic_refraction_dioptres(400.0), 1.68524 - 0.63346 / 0.18590, 1e-12);
  EXPECT_NEAR(chromatic_refraction_dioptres(400.0), -1.7223, 1e-4);
  EXPECT_NEAR(chromatic_refraction_dioptres(700.0), 0.3816, 1e-4);
  EXPECT_NEAR(kLcaZeroWavelengthNm, 589.99, 0.01);  // the sodium D line the paper refers to
  EXPECT_NEAR(chromatic_refraction_dioptres(kLcaZeroWavelengthNm), 0.0, 1e-12);
  EXPECT_THROW(chromatic_refraction_dioptres(214.0), std::invalid_argument);
}

TEST(GlareChromaticEye, DefocusBetween400And700nmMatchesThePapersReducedEye) {
  // 2.104 D between 400 and 700 nm by the fit, 2.103 D by the reduced eye it summarises.
  const double fit = chromatic_refraction_dioptres(700.0) - chromatic_refraction_dioptres(400.0);
  const double reduced_eye = reduced_eye_refraction_dioptres(700.0) - reduced_eye_refraction_dioptres(400.0);
  EXPECT_NEAR(fit, 2.1039, 1e-4);
  EXPECT_NEAR(fit, reduced_eye, 0.002);
  for (double wavelength_nm = 380.0; wavelength_nm <= 770.0; wavelength_nm += 10.0)
    EXPECT_NEAR(chromatic_refraction_dioptres(wavelength_nm) - chromatic_refraction_dioptres(589.0),
                reduced_eye_refraction_dioptres(wavelength_nm) - reduced_eye_refraction_dioptres(589.0), 0.003)
        << wavelength_nm << " nm";
}

TEST(GlareChromaticEye, ExcessPowerIsPositiveTowardTheBlue) {
  // The eye converges blue more: relative to 575 nm it has +1.65 D at 400 nm and -0.45 D at 700 nm.
  EXPECT_NEAR(chromatic_power_excess_dioptres(575.0, 575.0), 0.0, 1e-15);
  EXPECT_NEAR(chromatic_power_excess_dioptres(400.0, 575.0), chromatic_refraction_dioptres(575.0) + 1.7223, 1e-4);
  EXPECT_GT(chromatic_power_excess_dioptres(400.0, 575.0), 1.6);
  EXPECT_LT(chromatic_power_excess_dioptres(700.0, 575.0), -0.4);
  EXPECT_NEAR(chromatic_power_excess_dioptres(400.0, 575.0) - chromatic_power_excess_dioptres(700.0, 575.0), 2.1039, 1e-4);
}

}  // namespace
}  // namespace glarelab

// The astigmatic pupil phase against glare/wave/fresnel.h's spherical defocus and a hand-worked oblique case.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "glare/eye/aperture_raster.h"
#include "glare/refraction/astigmatic_phase.h"

namespace glarelab {
namespace {

TEST(AstigmaticPhase, SphericalErrorIsFresnelsDefocusPhaseSampleForSample) {
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 4.0;
  ApertureRasterOptions options;
  options.grid_px = 64;
  options.aperture_width_mm = 8.0;
  const ApertureGrid grid = rasterise_aperture(geometry, options);
  const auto spherical = apply_quadratic_phase(grid, phase_coefficient_per_m2(PhaseForm::defocus, 575.0, 1.5));
  const auto general = apply_power_error_phase(grid, DioptricPower::spherical(1.5), 575.0);
  ASSERT_EQ(spherical.size(), general.size());
  for (std::size_t k = 0; k < general.size(); ++k) EXPECT_LT(std::abs(spherical[k] - general[k]), 1e-12) << k;
}

TEST(AstigmaticPhase, ObliqueCrossTermByHand) {
  // Plano / -2 x 45 (TABO): E = [[-1, -1], [-1, -1]] D. At (1 mm, 1 mm): W = p^T E p / 2 = -2e-6 m,
  // phi = 2 pi W / lambda with lambda = 500 nm: -8 pi. At (1 mm, -1 mm) W = 0.
  const DioptricPower error = DioptricPower::from_prescription({0.0, -2.0, 45.0});
  EXPECT_NEAR(power_error_phase_rad(error, 500.0, 1e-3, 1e-3), -8.0 * std::numbers::pi, 1e-9);
  EXPECT_NEAR(power_error_phase_rad(error, 500.0, 1e-3, -1e-3), 0.0, 1e-9);
}

TEST(AstigmaticPhase, SamplingCheckUsesTheStrongestMeridian) {
  // -1 / -3 x 10: principal powers -1 and -4 D; the check equals a spherical 4 D defocus's.
  const DioptricPower error = DioptricPower::from_prescription({-1.0, -3.0, 10.0});
  const PhaseSamplingReport astigmatic = check_power_error_sampling(error, 575.0, 3.0, 0.02, 10.0);
  const PhaseSamplingReport spherical =
      check_phase_sampling(phase_coefficient_per_m2(PhaseForm::defocus, 575.0, 4.0), 3.0, 0.02, 10.0);
  EXPECT_DOUBLE_EQ(astigmatic.max_phase_step_rad, spherical.max_phase_step_rad);
  EXPECT_DOUBLE_EQ(astigmatic.max_pixel_mm, spherical.max_pixel_mm);
  EXPECT_EQ(astigmatic.aliased, spherical.aliased);
}

}  // namespace
}  // namespace glarelab

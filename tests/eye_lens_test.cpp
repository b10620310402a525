// The lens: 750 particles inside the lens volume, moved by the 17 x 17 mass-spring deformation;
// 200 fibre gratings in the cortex annulus with the halo-forming period (Ritschel 3.3, Spencer 1995).
#include <gtest/gtest.h>

#include <cmath>

#include "glare/eye/eye_model.h"
#include "glare/eye/lens_model.h"

namespace glarelab {
namespace {

constexpr double kPi = 3.14159265358979323846;

double distance_to_segment(double px, double py, const ApertureLine& line) {
  const double dx = line.x1_mm - line.x0_mm, dy = line.y1_mm - line.y0_mm;
  const double t = std::clamp(((px - line.x0_mm) * dx + (py - line.y0_mm) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
  return std::hypot(px - (line.x0_mm + t * dx), py - (line.y0_mm + t * dy));
}

TEST(EyeLens, SevenHundredFiftyParticlesInsideTheLensVolume) {
  const EyeParameters p;
  const LensModel lens(p, 4);
  ASSERT_EQ(lens.particles().size(), 750u);
  const double radius = p.lens_equatorial_radius_mm, half = 0.5 * p.lens_thickness_mm;
  double smallest = 1e9, largest = 0.0, mean_r2 = 0.0;
  for (const LensParticle& particle : lens.particles()) {
    EXPECT_LE(std::pow(particle.r_mm / radius, 2) + std::pow(particle.z_mm / half, 2), 1.0);
    smallest = std::min(smallest, particle.diameter_mm);
    largest = std::max(largest, particle.diameter_mm);
    mean_r2 += particle.r_mm * particle.r_mm / 750.0;
  }
  EXPECT_GE(smallest, p.lens_particle_diameter_min_mm);
  EXPECT_LE(largest, p.lens_particle_diameter_max_mm);
  EXPECT_GT(largest - smallest, 0.5 * (p.lens_particle_diameter_max_mm - p.lens_particle_diameter_min_mm))
      << "particles must vary in size";
  // Uniform in the ellipsoid's volume: E[r^2] = (2/5) R^2 for an ellipsoid of revolution.
  EXPECT_NEAR(mean_r2, 0.4 * radius * radius, 0.05 * 0.4 * radius * radius);
  // Projected at rest, every particle lies within the lens's outline.
  std::vector<ApertureDisc> discs;
  lens.append_particles(0.0, discs);
  ASSERT_EQ(discs.size(), 750u);
  for (const ApertureDisc& disc : discs) EXPECT_LE(std::hypot(disc.centre_x_mm, disc.centre_y_mm), radius + 1e-12);
}

TEST(EyeLens, MassSpringGridIsInEquilibriumAndDrivenByOneElement) {
  const EyeParameters p;
  const LensDeformation deformation(p);
  EXPECT_EQ(deformation.nodes_per_side(), 17);
  EXPECT_LT(deformation.residual(), 1e-9);
  const int n = deformation.nodes_per_side();
  EXPECT_DOUBLE_EQ(deformation.node_unit_response(n - 1, n / 2).radial_mm, 1.0);  // the driver
  for (int j = 0; j < n; ++j) EXPECT_EQ(deformation.node_unit_response(0, j).radial_mm, 0.0);  // the axis
  // Bilinear interpolation reproduces the nodes and lies between them.
  const double dr = p.lens_equatorial_radius_mm / (n - 1), dz = p.lens_thickness_mm / (n - 1);
  const double z0 = -0.5 * p.lens_thickness_mm;
  const auto node = deformation.node_unit_response(10, 5);
  EXPECT_NEAR(deformation.displacement(10 * dr, z0 + 5 * dz, 0.01).radial_mm, 0.01 * node.radial_mm, 1e-15);
  const auto a = deformation.node_unit_response(10, 5).radial_mm, b = deformation.node_unit_response(11, 5).radial_mm;
  EXPECT_NEAR(deformation.displacement(10.5 * dr, z0 + 5 * dz, 1.0).radial_mm, 0.5 * (a + b), 1e-12);
  // The equator pulls the lens: nodes near the driver move most, the response decays inwards.
  EXPECT_GT(deformation.node_unit_response(n - 2, n / 2).radial_mm, deformation.node_unit_response(n / 2, n / 2).radial_mm);
}

TEST(EyeLens, AccommodationMovesTheParticles) {
  const EyeParameters p;
  const LensModel lens(p, 4);
  std::vector<ApertureDisc> rest, accommodated;
  lens.append_particles(0.0, rest);
  const double equator = lens.equator_displacement_mm(0.2);  // +0.2 D: the equator moves inwards
  EXPECT_NEAR(equator, -0.2 * p.lens_equator_displacement_mm_per_dioptre, 1e-15);
  lens.append_particles(equator, accommodated);
  double largest = 0.0;
  for (std::size_t k = 0; k < rest.size(); ++k)
    largest = std::max(largest, std::hypot(accommodated[k].centre_x_mm - rest[k].centre_x_mm,
                                           accommodated[k].centre_y_mm - rest[k].centre_y_mm));
  EXPECT_GT(largest, 0.1 * std::abs(equator));
  EXPECT_LE(largest, 1.5 * std::abs(equator));
}

TEST(EyeLens, TwoHundredGratingsWithTheHaloPeriodInTheCortexAnnulus) {
  const EyeParameters p;
  const LensModel lens(p, 4);
  const int per_grating = p.lens_grating_lines_per_grating;
  ASSERT_EQ(lens.grating_lines().size(), static_cast<std::size_t>(200 * per_grating));
  // Spencer 1995 Eq. 4, sin(theta) = lambda / e: the halo at 3 degrees for 568 nm.
  EXPECT_NEAR(std::asin(568e-6 / p.lens_grating_period_mm) * 180.0 / kPi, 3.0, 1e-9);
  EXPECT_NEAR(p.lens_grating_period_mm * 1000.0, 10.85, 0.01);
  for (std::size_t k = 0; k < lens.grating_lines().size(); ++k) {
    const ApertureLine& line = lens.grating_lines()[k];
    for (const double r : {std::hypot(line.x0_mm, line.y0_mm), std::hypot(line.x1_mm, line.y1_mm)}) {
      EXPECT_GE(r, p.lens_cortex_inner_radius_mm);
      EXPECT_LE(r, p.lens_equatorial_radius_mm);
    }
    EXPECT_NEAR(line.width_mm, 0.5 * p.lens_grating_period_mm, 1e-15);
    if (k % per_grating != 0) {  // neighbours in one grating are one period apart and parallel
      const ApertureLine& previous = lens.grating_lines()[k - 1];
      EXPECT_NEAR(distance_to_segment(line.x0_mm, line.y0_mm, previous), p.lens_grating_period_mm, 1e-9);
    }
  }
}

TEST(EyeLens, SmallPupilHidesTheGratings) {
  const EyeParameters p;
  const LensModel lens(p, 4);
  // Spencer 1995: a beam under 3 mm passes through the clear lens; a 2 mm pupil sees no grating.
  for (const ApertureLine& line : lens.grating_lines())
    EXPECT_GT(distance_to_segment(0.0, 0.0, line) - 0.5 * line.width_mm, 1.0);
  EXPECT_FALSE(lens.gratings_visible(2.0));
  EXPECT_TRUE(lens.gratings_visible(6.0));

  // Through the eye model: a bright field (Eq. 2: ~2 mm) leaves the gratings out, a dark one keeps them.
  EyeParameters bright = p, dark = p;
  bright.initial_field_luminance_cd_m2 = 1e4;
  dark.initial_field_luminance_cd_m2 = 0.01;
  const EyeModel bright_eye(bright, 4), dark_eye(dark, 4);
  EXPECT_FALSE(bright_eye.state_at(1.0).gratings_in_pupil);
  const std::size_t lashes = static_cast<std::size_t>(p.upper_eyelash_count + p.lower_eyelash_count);
  EXPECT_EQ(bright_eye.geometry_at(1.0).lines.size(), lashes);
  EXPECT_EQ(dark_eye.geometry_at(1.0).lines.size(), lashes + lens.grating_lines().size());
}

}  // namespace
}  // namespace glarelab

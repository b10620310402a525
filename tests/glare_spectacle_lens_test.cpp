// Spectacle lenses traced as real thick lenses (glare/refraction/spectacle_lens.h, glare/refraction/spectacle_power.h)
// against the thick-lens formulas, Prentice's rule, the Abbe number's definition and hand-worked
// values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <numbers>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>
#include <glm/mat2x2.hpp>

#include "glare/refraction/spectacle_lens.h"
#include "glare/refraction/spectacle_power.h"

namespace glarelab {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

SpectacleLensSpec lens_spec(SpheroCylinder prescription) {
  SpectacleLensSpec spec;
  spec.prescription = prescription;
  return spec;
}

TEST(SpectacleLens, BackSurfaceFollowsTheThickLensFormulaHandWorked) {
  // +4.00 DS in CR-39 (n_d 1.498), 4.0 mm thick; Vogel: base 4 + 6 = 10 D.
  // F1 / (1 - (t / n) F1) = 10 / (1 - 0.004 / 1.498 * 10) = 10.274348 D, so F2 = 4 - 10.274348.
  SpectacleLensSpec spec = lens_spec({4.0, 0.0, 0.0});
  spec.centre_thickness_mm = 4.0;
  const SpectacleLens lens(spec);
  EXPECT_DOUBLE_EQ(lens.front_power_dioptres(), 10.0);
  EXPECT_NEAR(lens.back_surface_power().xx(), -6.274348422, 1e-8);
  EXPECT_NEAR(lens.back_surface_power().yy(), -6.274348422, 1e-8);
  // Front radius (n - 1) / F1 = 49.8 mm: curvature 1 / 0.0498 m.
  EXPECT_NEAR(lens.front_sphere().sweep_curvature_per_m, 10.0 / 0.498, 1e-9);
  // Vogel for minus lenses: -6 / 2 + 6 = 3 D; with a cylinder, on the spherical equivalent -3.
  EXPECT_DOUBLE_EQ(SpectacleLens(lens_spec({-6.0, 0.0, 0.0})).front_power_dioptres(), 3.0);
  EXPECT_DOUBLE_EQ(SpectacleLens(lens_spec({-2.0, -2.0, 90.0})).front_power_dioptres(), 4.5);
}

TEST(SpectacleLens, DefaultThicknessLeavesTwoMillimetresAtTheCentreOrOneAtTheEdge) {
  const SpectacleLens minus(lens_spec({-6.0, 0.0, 0.0}));
  EXPECT_NEAR(minus.centre_thickness_m(), 2.0e-3, 1e-12);
  EXPECT_NEAR(minus.minimum_thickness_m(), 2.0e-3, 1e-12);  // a minus lens is thinnest at its centre
  const glm::dvec2 rim(0.025, 0.0);
  EXPECT_GT(minus.centre_thickness_m() - minus.front_sag(rim).sag_m + minus.back_sag(rim).sag_m, 5e-3);
  const SpectacleLens plus(lens_spec({4.0, 0.0, 0.0}));
  EXPECT_NEAR(plus.minimum_thickness_m(), 1.0e-3, 1e-6);
  // Hand-worked at the 25 mm rim: front R1 = 0.498 / 10 m = 49.8 mm, sag 49.8 - sqrt(49.8^2 - 25^2)
  // = 6.730 mm; with t = 3.70 mm, F1 / (1 - (t / n) F1) = 10.2533 D, F2 = -6.2533 D, R2 = 0.498 /
  // 6.2533 m = 79.64 mm, sag 79.64 - sqrt(79.64^2 - 25^2) = 4.025 mm; t = 1 + 6.730 - 4.025 = 3.705 mm.
  EXPECT_NEAR(plus.centre_thickness_m(), 3.705e-3, 0.01e-3);
}

TEST(SpectacleLens, CauchyDispersionMatchesTheAbbeNumber) {
  const SpectacleLens lens(lens_spec({-2.0, 0.0, 0.0}));
  EXPECT_NEAR(lens.refractive_index(kFraunhoferD_nm), 1.498, 1e-12);
  EXPECT_NEAR(lens.refractive_index(kFraunhoferF_nm) - lens.refractive_index(kFraunhoferC_nm), 0.498 / 58.0, 1e-12);
  // Hand-worked Cauchy coefficients: B = (0.498 / 58) / (1 / 0.48613^2 - 1 / 0.65627^2) = 0.0044962 um^2,
  // A = 1.498 - B / 0.58756^2 = 1.484976.
  EXPECT_NEAR(lens.refractive_index(1e6), 1.484976, 1e-6);
  EXPECT_GT(lens.refractive_index(450.0), lens.refractive_index(650.0));
}

// The thin-lens limit: on the primary line of sight the traced pencil's vergence at the back vertex
// is the prescription in every meridian, however the cylinder axis turns (Harris' F = S I + C n n^T).
TEST(SpectacleLens, PrimaryGazePowerIsThePrescriptionInEveryMeridian) {
  const SpheroCylinder prescriptions[] = {
      {4.0, 0.0, 0.0}, {-6.0, 0.0, 0.0}, {-2.0, -1.5, 30.0}, {1.25, -2.0, 135.0}, {0.0, -3.0, 90.0}, {-4.5, -0.75, 5.0}, {3.0, -1.0, 180.0}};
  for (const SpheroCylinder& prescription : prescriptions) {
    for (double thickness_mm : {0.0, 6.0}) {  // 0: the default rule
      SpectacleLensSpec spec = lens_spec(prescription);
      if (thickness_mm > 0.0) spec.centre_thickness_mm = thickness_mm;
      const SpectacleLens lens(spec);
      const GazePower power = lens_power_at_gaze(lens, glm::dvec3(0.0, 0.0, 1.0), kFraunhoferD_nm);
      ASSERT_TRUE(power.through);
      const DioptricPower expected = DioptricPower::from_prescription(prescription);
      for (double meridian = 0.0; meridian < 180.0; meridian += 15.0)
        EXPECT_NEAR(power.vertex_sphere.meridian_dioptres(meridian), expected.meridian_dioptres(meridian), 1e-4)
            << prescription.sphere_dioptres << " / " << prescription.cylinder_dioptres << " x " << prescription.axis_deg
            << ", t " << thickness_mm << " mm, meridian " << meridian;
      // At the cornea: F (I - d F)^-1 with d the vertex distance; for +4 D, 4 / (1 - 0.012 * 4).
      const DioptricPower cornea = effective_power_at_distance(expected, 0.012);
      EXPECT_NEAR(power.at_cornea.xx(), cornea.xx(), 1e-4);
      EXPECT_NEAR(power.at_cornea.xy(), cornea.xy(), 1e-4);
      EXPECT_NEAR(power.at_cornea.yy(), cornea.yy(), 1e-4);
    }
  }
}

TEST(SpectacleLens, ThinLensLimitSurfacePowersAddToThePrescription) {
  // As t -> 0 the shape factor vanishes and F1 + F2 = F_v in every meridian (thin-lens addition).
  for (const SpheroCylinder& prescription : {SpheroCylinder{2.0, -1.0, 60.0}, SpheroCylinder{-5.0, -2.0, 160.0}}) {
    SpectacleLensSpec spec = lens_spec(prescription);
    spec.diameter_mm = 4.0;
    spec.centre_thickness_mm = 0.05;
    const SpectacleLens lens(spec);
    const DioptricPower sum = lens.back_surface_power() + DioptricPower::spherical(lens.front_power_dioptres());
    const DioptricPower expected = DioptricPower::from_prescription(prescription);
    // The residual is the shape factor's (t / n) F1^2 ~ 0.05e-3 / 1.5 * 36 = 0.0012 D.
    EXPECT_NEAR(sum.xx(), expected.xx(), 2e-3);
    EXPECT_NEAR(sum.xy(), expected.xy(), 2e-3);
    EXPECT_NEAR(sum.yy(), expected.yy(), 2e-3);
    const GazePower power = lens_power_at_gaze(lens, glm::dvec3(0.0, 0.0, 1.0), kFraunhoferD_nm);
    EXPECT_NEAR(power.vertex_sphere.xx(), expected.xx(), 1e-4);
    EXPECT_NEAR(power.vertex_sphere.xy(), expected.xy(), 1e-4);
    EXPECT_NEAR(power.vertex_sphere.yy(), expected.yy(), 1e-4);
  }
}

// Spectacle magnification for the turning eye, from the ray trace's slope at the centre:
// SM = [1 / (1 - h F_v)] [1 / (1 - (t / n) F1)], h from the back vertex to the centre of rotation.
TEST(SpectacleLens, CentralAngularMagnificationIsTheSpectacleMagnification) {
  for (const auto& [power, thickness_mm] : {std::pair{4.0, 4.0}, std::pair{-6.0, 2.0}}) {
    SpectacleLensSpec spec = lens_spec({power, 0.0, 0.0});
    spec.centre_thickness_mm = thickness_mm;
    const SpectacleLens lens(spec);
    const double h_m = (spec.vertex_distance_mm + spec.centre_of_rotation_mm) * 1e-3;
    const double expected = 1.0 / (1.0 - h_m * power) / (1.0 - thickness_mm * 1e-3 / 1.498 * lens.front_power_dioptres());
    const double tangent = 1e-4;
    const LensRay ray = lens.trace_from_eye(glm::dvec3(tangent, 0.0, 1.0), kFraunhoferD_nm);
    ASSERT_TRUE(ray.through());
    EXPECT_NEAR(tangent / (ray.direction.x / ray.direction.z), expected, 1e-5) << power;
  }
}

// The same from lens_power_at_gaze, as a matrix: for a cylinder the magnification differs by
// meridian, d(scene angle) / d(visual angle) = (1 - (t / n) F1) (I - h F_v) with F_v the power matrix
// (the power factor per meridian, the shape factor spherical since the front is).
TEST(SpectacleLens, AngularMagnificationMatrixFollowsTheCylinder) {
  for (const SpheroCylinder& prescription : {SpheroCylinder{4.0, 0.0, 0.0}, SpheroCylinder{-2.0, -3.0, 30.0}, SpheroCylinder{1.0, -2.0, 135.0}}) {
    SpectacleLensSpec spec = lens_spec(prescription);
    spec.centre_thickness_mm = 5.0;
    const SpectacleLens lens(spec);
    const GazePower power = lens_power_at_gaze(lens, glm::dvec3(0.0, 0.0, 1.0), kFraunhoferD_nm);
    ASSERT_TRUE(power.through);
    const double shape = 1.0 - 0.005 / 1.498 * lens.front_power_dioptres();
    const glm::dmat2 expected = shape * (glm::dmat2(1.0) - 0.0255 * DioptricPower::from_prescription(prescription).matrix_dioptres);
    for (int column = 0; column < 2; ++column)
      for (int row = 0; row < 2; ++row)
        EXPECT_NEAR(power.scene_per_visual_angle[column][row], expected[column][row], 1e-6)
            << prescription.sphere_dioptres << " / " << prescription.cylinder_dioptres << " x " << prescription.axis_deg;
  }
}

// Prentice's rule: decentred by c, the primary line of sight passes the lens c from its optical
// centre and is deviated by c F. For the thick lens the ray is parallel to the axis inside the eye's
// space, so its paraxial deviation is c times the equivalent power F_e = F_v (1 - (t / n) F1).
TEST(SpectacleLens, DecentrationGivesPrenticePrism) {
  for (const double power : {4.0, -6.0}) {
    SpectacleLensSpec spec = lens_spec({power, 0.0, 0.0});
    spec.centre_thickness_mm = power > 0 ? 4.0 : 2.0;
    spec.decentration_mm = glm::dvec2(3.0, -2.0);  // optical centre 3 mm right, 2 mm down
    const SpectacleLens lens(spec);
    const double equivalent = power * (1.0 - *spec.centre_thickness_mm * 1e-3 / 1.498 * lens.front_power_dioptres());
    const LensRay ray = lens.trace_from_eye(glm::dvec3(0.0, 0.0, 1.0), kFraunhoferD_nm);
    ASSERT_TRUE(ray.through());
    // Prism dioptres: 100 tan(deviation). A plus lens sends the eye's ray toward its optical centre.
    const double prism_x = 100.0 * ray.direction.x / ray.direction.z, prism_y = 100.0 * ray.direction.y / ray.direction.z;
    EXPECT_NEAR(prism_x, 0.3 * equivalent, 0.01 * std::abs(0.3 * equivalent)) << power;
    EXPECT_NEAR(prism_y, -0.2 * equivalent, 0.01 * std::abs(0.2 * equivalent)) << power;
  }
}

TEST(SpectacleLens, ListingFrameTurnsTheObserverFrameToTheGaze) {
  const ListingFrame primary = listing_eye_frame(glm::dvec3(0.0, 0.0, 2.0));
  EXPECT_DOUBLE_EQ(primary.right.x, 1.0);
  EXPECT_DOUBLE_EQ(primary.up.y, 1.0);
  const ListingFrame down = listing_eye_frame(glm::dvec3(0.0, -std::sin(0.5), std::cos(0.5)));
  EXPECT_NEAR(down.right.x, 1.0, 1e-15);  // a vertical turn keeps the horizontal axis
  EXPECT_NEAR(down.up.y, std::cos(0.5), 1e-15);
  EXPECT_NEAR(down.up.z, std::sin(0.5), 1e-15);
  const ListingFrame oblique = listing_eye_frame(glm::dvec3(0.3, 0.4, 1.0));
  EXPECT_NEAR(glm::dot(oblique.right, oblique.up), 0.0, 1e-15);
  EXPECT_NEAR(glm::dot(oblique.right, oblique.gaze), 0.0, 1e-15);
  EXPECT_NEAR(glm::dot(oblique.up, oblique.gaze), 0.0, 1e-15);
}

// A second implementation of the oblique power: Kakimoto et al. 2007's wavefront tracing (section
// 4.3) along the chief ray of a spherical lens, with the surfaces intersected as spheres. A plane
// wave from the scene (kappa = 0) is refracted at the front surface by Eq. 4, transferred through the
// glass by Eq. 1, refracted at the back surface and transferred to the vertex sphere. For a centred
// spherical lens the chief ray stays in one meridional plane, so u (Eq. 2: N x N_s) is the sagittal
// direction at both surfaces and the torsion stays 0 (Eqs. 3 and 5 reduce to the identity); Eq. 4
// is then Coddington's sagittal and tangential equations. Curvatures: positive toward the direction
// the wave moves (so a surface whose centre lies on the eye's side has kappa_s = c > 0).
struct SphereHit {
  glm::dvec3 point;
  glm::dvec3 normal;
};
SphereHit intersect_sphere(glm::dvec3 origin, glm::dvec3 direction, double vertex_z, double curvature) {
  const glm::dvec3 centre(0.0, 0.0, vertex_z - 1.0 / curvature);
  const glm::dvec3 offset = origin - centre;
  const double b = glm::dot(offset, direction), c = glm::dot(offset, offset) - 1.0 / (curvature * curvature);
  const double root = std::sqrt(b * b - c);
  const glm::dvec3 first = origin + (-b - root) * direction, second = origin + (-b + root) * direction;
  const glm::dvec3 point = std::abs(first.z - vertex_z) < std::abs(second.z - vertex_z) ? first : second;
  return {point, glm::normalize(point - centre)};
}
glm::dvec3 snell(glm::dvec3 d, glm::dvec3 normal, double mu) {
  const glm::dvec3 n = glm::dot(normal, d) > 0.0 ? normal : -normal;
  const double cos_i = glm::dot(d, n);
  return glm::normalize(mu * d + (std::sqrt(1.0 - mu * mu * (1.0 - cos_i * cos_i)) - mu * cos_i) * n);
}
// Eq. 4 for a spherical surface in the sagittal (u) and tangential (v) directions, torsion 0.
void refract_wavefront(double& sagittal, double& tangential, double mu, double cos_in, double cos_out, double surface) {
  const double gamma = cos_out - mu * cos_in;
  sagittal = mu * sagittal + gamma * surface;
  tangential = mu * tangential * cos_in * cos_in / (cos_out * cos_out) + gamma * surface / (cos_out * cos_out);
}
void transfer_wavefront(double& sagittal, double& tangential, double distance) {  // Eq. 1
  sagittal = sagittal / (1.0 - distance * sagittal);
  tangential = tangential / (1.0 - distance * tangential);
}

TEST(SpectacleLens, ObliquePowerMatchesKakimotoWavefrontTracing) {
  for (const auto& [power, thickness_mm] : {std::pair{4.0, 4.0}, std::pair{-6.0, 2.0}}) {
    SpectacleLensSpec spec = lens_spec({power, 0.0, 0.0});
    spec.centre_thickness_mm = thickness_mm;
    const SpectacleLens lens(spec);
    const double n = lens.refractive_index(kFraunhoferD_nm);
    const double c1 = lens.front_power_dioptres() / (n - 1.0), c2 = lens.back_surface_power().xx() / (1.0 - n);
    for (const glm::dvec3 gaze : {glm::dvec3(0.0, -0.577, 1.0), glm::dvec3(-0.364, -0.364, 1.0), glm::dvec3(0.7, 0.0, 1.0)}) {
      const glm::dvec3 g = glm::normalize(gaze);
      // The chief ray from the centre of rotation outward, then the wave along it inward.
      const SphereHit back = intersect_sphere(glm::dvec3(0.0), g, lens.back_vertex_z_m(), c2);
      const glm::dvec3 inside = snell(g, back.normal, 1.0 / n);
      const SphereHit front = intersect_sphere(back.point, inside, lens.front_vertex_z_m(), c1);
      const glm::dvec3 scene = snell(inside, front.normal, n);
      const double cos_front_air = std::abs(glm::dot(scene, front.normal)), cos_front_glass = std::abs(glm::dot(inside, front.normal));
      const double cos_back_glass = std::abs(glm::dot(inside, back.normal)), cos_back_air = std::abs(glm::dot(g, back.normal));
      double sagittal = 0.0, tangential = 0.0;  // plane wave from a distant point
      refract_wavefront(sagittal, tangential, 1.0 / n, cos_front_air, cos_front_glass, c1);
      transfer_wavefront(sagittal, tangential, glm::length(front.point - back.point));
      refract_wavefront(sagittal, tangential, n, cos_back_glass, cos_back_air, c2);
      transfer_wavefront(sagittal, tangential, glm::length(back.point) - lens.vertex_sphere_radius_m());
      // The sagittal direction is the Listing axis z x g, the same in the eye's frame as in the
      // observer's (Listing's rotation leaves its own axis fixed).
      const glm::dvec3 axis = glm::normalize(glm::cross(glm::dvec3(0.0, 0.0, 1.0), g));
      const double sagittal_deg = std::atan2(axis.y, axis.x) * kDegPerRad;
      const GazePower traced = lens_power_at_gaze(lens, gaze, kFraunhoferD_nm);
      ASSERT_TRUE(traced.through);
      EXPECT_NEAR(traced.scene_direction.x, scene.x, 1e-12);
      EXPECT_NEAR(traced.scene_direction.y, scene.y, 1e-12);
      EXPECT_NEAR(traced.vertex_sphere.meridian_dioptres(sagittal_deg), sagittal, 1e-5) << power << " D, gaze " << gaze.x << ", " << gaze.y;
      EXPECT_NEAR(traced.vertex_sphere.meridian_dioptres(sagittal_deg + 90.0), tangential, 1e-5) << power << " D, gaze " << gaze.x << ", " << gaze.y;
      std::printf("%+.1f D at %.1f deg from the axis: sagittal %.4f D, tangential %.4f D (wavefront), %.4f / %.4f D (rays)\n", power,
                  std::acos(g.z) * kDegPerRad, sagittal, tangential, traced.vertex_sphere.meridian_dioptres(sagittal_deg),
                  traced.vertex_sphere.meridian_dioptres(sagittal_deg + 90.0));
    }
  }
}

// Progressive: at the fitting cross the distance power; through the near zone, distance + add.
TEST(SpectacleLens, ProgressiveNearZoneAddsTheAddToTheDistancePower) {
  for (const double distance_power : {0.0, 2.0, -3.0}) {
    SpectacleLensSpec spec = lens_spec({distance_power, 0.0, 0.0});
    spec.near_add_dioptres = 2.0;
    spec.corridor_length_mm = 14.0;
    const SpectacleLens lens(spec);
    const GazePower distance = lens_power_at_gaze(lens, glm::dvec3(0.0, 0.0, 1.0), kFraunhoferD_nm);
    ASSERT_TRUE(distance.through);
    EXPECT_NEAR(distance.vertex_sphere.xx(), distance_power, 1e-4);
    EXPECT_NEAR(distance.vertex_sphere.yy(), distance_power, 1e-4);
    // The line of sight through the front surface s mm below the fitting cross: at the near
    // reference point (s = 14, where the design puts distance + add on the vertex sphere) and 1 mm
    // above and below it, where nothing was fitted (ISO 8980-2's add tolerance, 0.12 D, as the
    // bound; further down, obliquity lowers the mean power: docs/SPECTACLES.md).
    for (const double below_mm : {14.0, 13.0, 15.0}) {
      double tangent = 0.0;
      for (int iteration = 0; iteration < 40; ++iteration) {
        const LensRay ray = lens.trace_from_eye(glm::dvec3(0.0, -tangent, 1.0), kFraunhoferD_nm);
        tangent += (below_mm * 1e-3 + ray.origin_m.y) / ray.origin_m.z;
      }
      const GazePower near = lens_power_at_gaze(lens, glm::dvec3(0.0, -tangent, 1.0), kFraunhoferD_nm);
      ASSERT_TRUE(near.through);
      const PrincipalPowers principal = principal_powers(near.vertex_sphere);
      std::printf("distance %+.2f D, add 2.00 D, %2.0f mm below the cross (gaze %.1f deg down): mean %.4f D, cylinder %.4f D\n",
                  distance_power, below_mm, std::atan(tangent) * kDegPerRad, near.vertex_sphere.mean_dioptres(),
                  principal.p2_dioptres - principal.p1_dioptres);
      EXPECT_NEAR(near.vertex_sphere.mean_dioptres(), distance_power + 2.0, below_mm == 14.0 ? 1e-4 : 0.12);
    }
  }
}

// Minkwitz's theorem (Minkwitz 1963): beside an umbilic line whose mean curvature changes, the
// surface astigmatism grows across the line at twice the rate the mean curvature grows along it,
// dA/dx = 2 |dH/dy|. Measured on the progressive front surface's true normal curvatures (the shape
// operator I^-1 II of the graph z = S(x, y), second derivatives by central differences of the
// analytic gradient) at the corridor's steepest point, 7 mm below the cross. The line is umbilic in
// the sag's second derivatives, so in normal curvatures it keeps a small astigmatism A0 from the
// slope there (0.7 % of the add); that part lies along the meridians and the twist's across them,
// so the twist's share is sqrt(A^2 - A0^2).
TEST(SpectacleLens, ProgressiveSurfaceObeysMinkwitz) {
  SpectacleLensSpec spec = lens_spec({0.0, 0.0, 0.0});
  spec.near_add_dioptres = 2.0;
  const SpectacleLens lens(spec);
  struct Curvatures {
    double mean, astigmatism;
  };
  const auto curvatures = [&](glm::dvec2 at) {
    const double step = 1e-5;
    const glm::dvec2 gradient = lens.front_sag(at).gradient;
    const glm::dvec2 dx = (lens.front_sag(at + glm::dvec2(step, 0.0)).gradient - lens.front_sag(at - glm::dvec2(step, 0.0)).gradient) / (2.0 * step);
    const glm::dvec2 dy = (lens.front_sag(at + glm::dvec2(0.0, step)).gradient - lens.front_sag(at - glm::dvec2(0.0, step)).gradient) / (2.0 * step);
    const double cross = 0.5 * (dx.y + dy.x);
    const glm::dmat2 second = glm::dmat2(dx.x, cross, cross, dy.y) / std::sqrt(1.0 + glm::dot(gradient, gradient));
    const glm::dmat2 first(1.0 + gradient.x * gradient.x, gradient.x * gradient.y, gradient.x * gradient.y, 1.0 + gradient.y * gradient.y);
    const glm::dmat2 shape = glm::inverse(first) * second;
    const double mean = 0.5 * (shape[0][0] + shape[1][1]);
    return Curvatures{mean, 2.0 * std::sqrt(std::max(0.0, mean * mean - glm::determinant(shape)))};
  };
  const glm::dvec2 corridor(0.0, -7e-3);
  const double dh_dy = (curvatures(corridor + glm::dvec2(0.0, 1e-4)).mean - curvatures(corridor - glm::dvec2(0.0, 1e-4)).mean) / 2e-4;
  const double on_line = curvatures(corridor).astigmatism, beside = curvatures(corridor + glm::dvec2(5e-4, 0.0)).astigmatism;
  const double da_dx = std::sqrt(beside * beside - on_line * on_line) / 5e-4;
  EXPECT_LT(on_line, 0.01 * lens.progressive().full_add_curvature_per_m);
  EXPECT_NEAR(da_dx, 2.0 * std::abs(dh_dy), 0.02 * 2.0 * std::abs(dh_dy));
  // In dioptres per millimetre: (n - 1) times the curvature rates.
  std::printf("Minkwitz: mean power rises %.4f D/mm along the corridor, astigmatism %.4f D/mm across it (on the line %.4f D)\n",
              0.498 * std::abs(dh_dy) * 1e-3, 0.498 * da_dx * 1e-3, 0.498 * on_line);
}

void expect_refused(SpectacleLensSpec spec, const std::string& parameter) {
  try {
    SpectacleLens lens(spec);
    ADD_FAILURE() << "accepted a lens with bad " << parameter;
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("glare/refraction/spectacle_lens: "), std::string::npos) << message;
    EXPECT_NE(message.find(parameter), std::string::npos) << message;
  }
}

TEST(SpectacleLens, RefusesBadParametersNamingThem) {
  const SpectacleLensSpec good = lens_spec({-2.0, -1.0, 90.0});
  EXPECT_NO_THROW(SpectacleLens{good});
  for (double index : {1.0, 0.9, std::nan("")}) {
    SpectacleLensSpec spec = good;
    spec.refractive_index_d = index;
    expect_refused(spec, "refractive_index_d");
  }
  for (double abbe : {0.0, -30.0}) {
    SpectacleLensSpec spec = good;
    spec.abbe_number_d = abbe;
    expect_refused(spec, "abbe_number_d");
  }
  for (double axis : {-1.0, 180.5, 360.0}) {
    SpectacleLensSpec spec = good;
    spec.prescription.axis_deg = axis;
    expect_refused(spec, "axis_deg");
  }
  SpectacleLensSpec at_cornea = good;
  at_cornea.vertex_distance_mm = 0.0;
  expect_refused(at_cornea, "vertex_distance_mm");
  // +4 D over 50 mm needs about 2.5 mm more than its rim: 1.5 mm at the centre crosses the surfaces.
  SpectacleLensSpec thin_plus = lens_spec({4.0, 0.0, 0.0});
  thin_plus.centre_thickness_mm = 1.5;
  expect_refused(thin_plus, "centre_thickness_mm");
  SpectacleLensSpec no_thickness = good;
  no_thickness.centre_thickness_mm = 0.0;
  expect_refused(no_thickness, "centre_thickness_mm");
  // A -30 D lens' back surface (-21 D behind a -9 D Vogel front: radius 24 mm) cannot span 60 mm.
  SpectacleLensSpec steep = lens_spec({-30.0, 0.0, 0.0});
  steep.diameter_mm = 60.0;
  expect_refused(steep, "diameter_mm");
  // A corridor reaching past the 25 mm rim: its near reference point cannot be looked through.
  SpectacleLensSpec long_corridor = good;
  long_corridor.near_add_dioptres = 2.0;
  long_corridor.corridor_length_mm = 30.0;
  expect_refused(long_corridor, "corridor_length_mm");
  SpectacleLensSpec negative_add = good;
  negative_add.near_add_dioptres = -1.0;
  expect_refused(negative_add, "near_add_dioptres");
  // Axis 180 is the same meridian as 0 and is accepted.
  SpectacleLensSpec axis_180 = good;
  axis_180.prescription.axis_deg = 180.0;
  EXPECT_NO_THROW(SpectacleLens{axis_180});
}

}  // namespace
}  // namespace glarelab

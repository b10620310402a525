#include "glare/refraction/dioptric_power.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <glm/matrix.hpp>

namespace glarelab {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

double wrap_half_turn_deg(double angle_deg) {
  double wrapped = std::fmod(angle_deg, 180.0);
  if (wrapped < 0.0) wrapped += 180.0;
  if (wrapped >= 180.0) wrapped -= 180.0;  // fmod of -tiny + 180 can round to 180
  return wrapped;
}

}  // namespace

DioptricPower DioptricPower::spherical(double power_dioptres) { return {glm::dmat2(power_dioptres)}; }

DioptricPower DioptricPower::from_prescription(const SpheroCylinder& prescription) {
  const double alpha_rad = observer_axis_deg_from_tabo(prescription.axis_deg) / kDegPerRad;
  const glm::dvec2 normal(-std::sin(alpha_rad), std::cos(alpha_rad));
  // F = S I + C n n^T; glm::outerProduct(n, n) is symmetric, so its layout does not matter.
  return {glm::dmat2(prescription.sphere_dioptres) + prescription.cylinder_dioptres * glm::outerProduct(normal, normal)};
}

double DioptricPower::meridian_dioptres(double angle_deg) const {
  const double angle_rad = angle_deg / kDegPerRad;
  const glm::dvec2 direction(std::cos(angle_rad), std::sin(angle_rad));
  return glm::dot(direction, matrix_dioptres * direction);
}

PrincipalPowers principal_powers(const DioptricPower& power) {
  const double half_difference = 0.5 * (power.xx() - power.yy());
  const double radius = std::hypot(half_difference, power.xy());
  PrincipalPowers principal;
  principal.p1_dioptres = power.mean_dioptres() + radius;
  principal.p2_dioptres = power.mean_dioptres() - radius;
  // Direction of the larger eigenvalue: tan 2 phi = 2 F_xy / (F_xx - F_yy) (Kakimoto Eq. 5).
  principal.principal_angle_deg = radius == 0.0 ? 0.0 : wrap_half_turn_deg(0.5 * std::atan2(power.xy(), half_difference) * kDegPerRad);
  return principal;
}

SpheroCylinder DioptricPower::prescription() const {
  const PrincipalPowers principal = principal_powers(*this);
  SpheroCylinder prescription;
  prescription.sphere_dioptres = principal.p1_dioptres;  // along the axis: the more positive meridian
  prescription.cylinder_dioptres = principal.p2_dioptres - principal.p1_dioptres;
  prescription.axis_deg = prescription.cylinder_dioptres == 0.0 ? 0.0 : tabo_from_observer_axis_deg(principal.principal_angle_deg);
  return prescription;
}

double observer_axis_deg_from_tabo(double tabo_deg) { return wrap_half_turn_deg(180.0 - tabo_deg); }
double tabo_from_observer_axis_deg(double observer_axis_deg) { return wrap_half_turn_deg(180.0 - observer_axis_deg); }

DioptricPower effective_power_at_distance(const DioptricPower& power, double distance_m) {
  const glm::dmat2 shifted = glm::dmat2(1.0) - distance_m * power.matrix_dioptres;
  const double determinant = glm::determinant(shifted);
  if (!(std::abs(determinant) > 1e-12))
    throw std::invalid_argument("glare/refraction/dioptric_power: the lens focuses at " + std::to_string(distance_m * 1000.0) +
                                " mm, the plane its power is moved to; no finite effective power there");
  DioptricPower effective{power.matrix_dioptres * glm::inverse(shifted)};
  // F and (I - d F)^-1 commute (both are functions of F), so the product is symmetric; remove the
  // rounding asymmetry so every later eigen decomposition sees an exactly symmetric matrix.
  const double xy = 0.5 * (effective.matrix_dioptres[0][1] + effective.matrix_dioptres[1][0]);
  effective.matrix_dioptres[0][1] = effective.matrix_dioptres[1][0] = xy;
  return effective;
}

BlurEllipse geometric_blur_ellipse(const DioptricPower& error, double pupil_radius_m) {
  const PrincipalPowers principal = principal_powers(error);
  const double first = std::abs(principal.p1_dioptres), second = std::abs(principal.p2_dioptres);
  BlurEllipse ellipse;
  ellipse.semi_major_rad = std::max(first, second) * pupil_radius_m;
  ellipse.semi_minor_rad = std::min(first, second) * pupil_radius_m;
  ellipse.major_axis_angle_deg =
      first >= second ? principal.principal_angle_deg : wrap_half_turn_deg(principal.principal_angle_deg + 90.0);
  return ellipse;
}

}  // namespace glarelab

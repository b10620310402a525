#include "glare/refraction/eye_refraction.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace glarelab {
namespace {

void require(bool condition, const std::string& message) {
  if (!condition) throw std::invalid_argument("glare/refraction/eye_refraction: " + message);
}

// effective_power_at_distance with its error named for this subsystem.
DioptricPower moved(const DioptricPower& power, double distance_m, const std::string& what) {
  try {
    return effective_power_at_distance(power, distance_m);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument("glare/refraction/eye_refraction: " + what + " (" + error.what() + ")");
  }
}

}  // namespace

double emmetropic_power_dioptres() { return kVitreousIndex / kSchematicCorneaRetina_m; }

double hofstetter_amplitude_dioptres(double age_years) {
  require(std::isfinite(age_years) && age_years >= 0.0, "age must be a finite number of years >= 0");
  return std::max(0.0, 18.5 - 0.3 * age_years);
}

RefractiveEye::RefractiveEye(const EyeRefraction& refraction) : refraction_(refraction) {
  require(std::isfinite(refraction.accommodation_amplitude_dioptres) && refraction.accommodation_amplitude_dioptres >= 0.0,
          "the accommodation amplitude must be finite and >= 0 D");
  require(std::isfinite(refraction.prescription_vertex_distance_m) && refraction.prescription_vertex_distance_m >= 0.0,
          "the prescription's vertex distance must be finite and >= 0");
  const SpheroCylinder& rx = refraction.correcting_prescription;
  require(std::isfinite(rx.sphere_dioptres) && std::isfinite(rx.cylinder_dioptres) && std::isfinite(rx.axis_deg),
          "the prescription must be finite");
  ocular_refraction_ = moved(DioptricPower::from_prescription(rx), refraction.prescription_vertex_distance_m,
                             "the prescription focuses at the cornea");
}

DioptricPower RefractiveEye::relaxed_power() const {
  return DioptricPower::spherical(emmetropic_power_dioptres()) - ocular_refraction_;
}

EyePrincipalPowers RefractiveEye::relaxed_principal_powers() const {
  const PrincipalPowers principal = principal_powers(relaxed_power());
  EyePrincipalPowers eye;
  eye.p1_min_dioptres = principal.p1_dioptres;
  eye.p2_min_dioptres = principal.p2_dioptres;
  eye.mean_dioptres = 0.5 * (principal.p1_dioptres + principal.p2_dioptres);
  eye.astigmatism_dioptres = principal.p1_dioptres - principal.p2_dioptres;
  eye.p1_direction_deg = principal.principal_angle_deg;
  return eye;
}

double RefractiveEye::accommodation_dioptres(double mean_vergence_dioptres) const {
  // Eq. 13: Delta P = max(0, min(n2 / z_r - kappa-bar - P-bar_min, Delta_max)).
  const double wanted = emmetropic_power_dioptres() - mean_vergence_dioptres - relaxed_power().mean_dioptres();
  return std::clamp(wanted, 0.0, refraction_.accommodation_amplitude_dioptres);
}

DioptricPower RefractiveEye::power(double accommodation_dioptres) const {
  return relaxed_power() + DioptricPower::spherical(accommodation_dioptres);
}

DioptricPower RefractiveEye::residual_error(const DioptricPower& vergence_at_cornea, double accommodation_dioptres) const {
  // Eq. 7 in vergences (n1 = 1): the light leaves the lens with V + P and converges on the retina
  // when that equals n2 / z_r (Eq. 11 with a point focus).
  return vergence_at_cornea + power(accommodation_dioptres) - DioptricPower::spherical(emmetropic_power_dioptres());
}

DioptricPower vergence_at_cornea(double object_distance_m, const std::optional<ThinSpectacleLens>& spectacles) {
  require(object_distance_m > 0.0, "the object distance must be > 0 m");
  if (!spectacles) return DioptricPower::spherical(std::isinf(object_distance_m) ? 0.0 : -1.0 / object_distance_m);
  const double vertex_m = spectacles->vertex_distance_m;
  require(std::isfinite(vertex_m) && vertex_m >= 0.0, "the spectacles' vertex distance must be finite and >= 0");
  require(object_distance_m > vertex_m, "the object (" + std::to_string(object_distance_m * 1e3) +
                                            " mm from the cornea) must lie beyond the spectacle lens (" +
                                            std::to_string(vertex_m * 1e3) + " mm)");
  const double at_lens_dioptres = std::isinf(object_distance_m) ? 0.0 : -1.0 / (object_distance_m - vertex_m);
  const DioptricPower leaving_lens =
      DioptricPower::spherical(at_lens_dioptres) + DioptricPower::from_prescription(spectacles->prescription);
  // Transfer over the vertex distance, Eq. 1: kappa' = kappa / (1 - d kappa) per principal meridian.
  return moved(leaving_lens, vertex_m, "the light leaving the spectacle lens focuses at the cornea");
}

FixationRefraction refraction_at_fixation(const RefractiveEye& eye, const ViewingCondition& viewing) {
  FixationRefraction fixation;
  fixation.fixation_vergence = vergence_at_cornea(viewing.fixation_distance_m, viewing.spectacles);
  fixation.accommodation_dioptres = eye.accommodation_dioptres(fixation.fixation_vergence.mean_dioptres());
  fixation.residual = eye.residual_error(fixation.fixation_vergence, fixation.accommodation_dioptres);
  return fixation;
}

DioptricPower residual_error_at(const RefractiveEye& eye, const ViewingCondition& viewing, double object_distance_m) {
  const double accommodation = refraction_at_fixation(eye, viewing).accommodation_dioptres;
  return eye.residual_error(vergence_at_cornea(object_distance_m, viewing.spectacles), accommodation);
}

SturmSection sturm_conoid_section(const RefractiveEye& eye, const DioptricPower& vergence_at_cornea,
                                  double accommodation_dioptres, double pupil_radius_m) {
  // Eq. 7: kappa'_x = mu kappa_x + P_x / n2 (and y, xy), mu = n1 / n2, kappa = V / n1.
  const double mu = kAirIndex / kVitreousIndex;
  const DioptricPower curvature =
      vergence_at_cornea * (mu / kAirIndex) + eye.power(accommodation_dioptres) * (1.0 / kVitreousIndex);
  // Eq. 5: the principal curvatures and the direction of the first.
  const PrincipalPowers principal = principal_powers(curvature);
  SturmSection section;
  section.a_m = pupil_radius_m * (1.0 - principal.p1_dioptres * kSchematicCorneaRetina_m);
  section.b_m = pupil_radius_m * (1.0 - principal.p2_dioptres * kSchematicCorneaRetina_m);
  section.first_direction_deg = principal.principal_angle_deg;
  return section;
}

}  // namespace glarelab

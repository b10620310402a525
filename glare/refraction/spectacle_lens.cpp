#include "glare/refraction/spectacle_lens.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "glare/refraction/spectacle_power.h"

namespace glarelab {
namespace {

constexpr double kMmPerM = 1000.0;
constexpr double kDegPerRad = 180.0 / std::numbers::pi;
// The default thickness rule (SpectacleLensSpec::centre_thickness_mm).
constexpr double kDefaultMinimumCentre_m = 2.0e-3;
constexpr double kDefaultMinimumEdge_m = 1.0e-3;

[[noreturn]] void refuse(const std::string& message) { throw std::invalid_argument("glare/refraction/spectacle_lens: " + message); }

std::string number(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

void require_finite(double value, const char* name) {
  if (!std::isfinite(value)) refuse(std::string(name) + " must be a finite number (got " + number(value) + ")");
}

void require_positive(double value, const char* name, const char* unit) {
  if (!(value > 0.0) || !std::isfinite(value))
    refuse(std::string(name) + " must be above 0 " + unit + " (got " + number(value) + ")");
}

void validate(const SpectacleLensSpec& spec) {
  if (!(spec.refractive_index_d > 1.0) || !std::isfinite(spec.refractive_index_d))
    refuse("refractive_index_d must be above 1, the index of air (got " + number(spec.refractive_index_d) + ")");
  if (!(spec.abbe_number_d > 0.0) || !std::isfinite(spec.abbe_number_d))
    refuse("abbe_number_d must be above 0 (got " + number(spec.abbe_number_d) + ")");
  require_finite(spec.prescription.sphere_dioptres, "sphere_dioptres");
  require_finite(spec.prescription.cylinder_dioptres, "cylinder_dioptres");
  if (!(spec.prescription.axis_deg >= 0.0 && spec.prescription.axis_deg <= 180.0))
    refuse("axis_deg must lie in [0, 180] (TABO; got " + number(spec.prescription.axis_deg) + ")");
  require_positive(spec.vertex_distance_mm, "vertex_distance_mm", "mm");
  require_positive(spec.diameter_mm, "diameter_mm", "mm");
  require_positive(spec.centre_of_rotation_mm, "centre_of_rotation_mm", "mm");
  if (spec.centre_thickness_mm) require_positive(*spec.centre_thickness_mm, "centre_thickness_mm", "mm");
  if (spec.base_curve_dioptres) require_finite(*spec.base_curve_dioptres, "base_curve_dioptres");
  require_finite(spec.decentration_mm.x, "decentration_mm x");
  require_finite(spec.decentration_mm.y, "decentration_mm y");
  if (!(spec.near_add_dioptres >= 0.0) || !std::isfinite(spec.near_add_dioptres))
    refuse("near_add_dioptres must be 0 (single vision) or above (got " + number(spec.near_add_dioptres) + ")");
  if (spec.near_add_dioptres > 0.0) require_positive(spec.corridor_length_mm, "corridor_length_mm", "mm");
}

// Vogel's rule for the base (front) curve from the spherical equivalent (SpectacleLensSpec).
double vogel_base_curve_dioptres(const SpheroCylinder& prescription) {
  const double equivalent = prescription.sphere_dioptres + 0.5 * prescription.cylinder_dioptres;
  return equivalent >= 0.0 ? equivalent + 6.0 : 0.5 * equivalent + 6.0;
}

// Points of the aperture disc where the lens' thickness is checked: a polar grid out to the rim.
template <typename Visit>
void for_each_aperture_point(double radius_m, Visit&& visit) {
  visit(glm::dvec2(0.0));
  constexpr int kRings = 24, kSpokes = 360;
  for (int ring = 1; ring <= kRings; ++ring)
    for (int spoke = 0; spoke < kSpokes; ++spoke) {
      const double angle = 2.0 * std::numbers::pi * spoke / kSpokes;
      const double r = radius_m * ring / kRings;
      visit(glm::dvec2(r * std::cos(angle), r * std::sin(angle)));
    }
}

// The intersection of origin + tau direction with z = vertex_z - S(x, y), by Newton's method from
// the vertex plane: f(tau) = o_z + tau d_z - vertex_z + S, f' = d_z + grad S . d_xy.
struct SurfaceHit {
  bool hit = false;
  glm::dvec3 point_m{0.0};
  glm::dvec3 normal{0.0, 0.0, 1.0};  // unit, +z side
};

SurfaceHit intersect(const std::function<SagSample(glm::dvec2)>& sag, double vertex_z_m, glm::dvec3 origin_m,
                     glm::dvec3 direction) {
  SurfaceHit out;
  if (std::abs(direction.z) < 1e-9) return out;
  double tau = (vertex_z_m - origin_m.z) / direction.z;
  for (int iteration = 0; iteration < 60; ++iteration) {
    const glm::dvec3 at = origin_m + tau * direction;
    const SagSample s = sag(glm::dvec2(at.x, at.y));
    if (!s.valid) return out;
    const double f = at.z - vertex_z_m + s.sag_m;
    const double slope = direction.z + glm::dot(s.gradient, glm::dvec2(direction.x, direction.y));
    if (std::abs(slope) < 1e-12) return out;  // grazing
    const double step = f / slope;
    tau -= step;
    if (std::abs(step) < 1e-15) {
      const glm::dvec3 point = origin_m + tau * direction;
      const SagSample final_sample = sag(glm::dvec2(point.x, point.y));
      if (!final_sample.valid) return out;
      out.hit = true;
      out.point_m = point;
      out.normal = glm::normalize(glm::dvec3(final_sample.gradient, 1.0));
      return out;
    }
  }
  return out;
}

// Snell's law in vector form (Kakimoto et al. 2007, section 4.3, after Mitchell and Hanrahan 1992):
// N' = mu N + gamma N_s with mu = n1 / n2, gamma = cos(phi') - mu cos(phi), N_s the surface normal
// on the side the ray travels to. False on total internal reflection.
bool refract(glm::dvec3 direction, glm::dvec3 normal, double n_before, double n_after, glm::dvec3& refracted) {
  const glm::dvec3 surface_normal = glm::dot(normal, direction) >= 0.0 ? normal : -normal;
  const double mu = n_before / n_after;
  const double cos_incidence = glm::dot(direction, surface_normal);
  const double cos_squared = 1.0 - mu * mu * (1.0 - cos_incidence * cos_incidence);
  if (cos_squared < 0.0) return false;
  const double gamma = std::sqrt(cos_squared) - mu * cos_incidence;
  refracted = glm::normalize(mu * direction + gamma * surface_normal);
  return true;
}

}  // namespace

const char* describe(LensRayOutcome outcome) {
  switch (outcome) {
    case LensRayOutcome::through: return "passes through the lens";
    case LensRayOutcome::misses_back_surface: return "misses the back surface";
    case LensRayOutcome::misses_front_surface: return "misses the front surface";
    case LensRayOutcome::outside_aperture: return "passes outside the lens' diameter";
    case LensRayOutcome::total_internal_reflection: return "is totally reflected inside the lens";
  }
  return "?";
}

SpectacleLens::SpectacleLens(const SpectacleLensSpec& spec) : spec_(spec) {
  validate(spec_);
  const double n = spec_.refractive_index_d;
  const double radius_m = 0.5 * spec_.diameter_mm / kMmPerM;
  front_power_dioptres_ = spec_.base_curve_dioptres ? *spec_.base_curve_dioptres : vogel_base_curve_dioptres(spec_.prescription);
  back_vertex_z_m_ = (spec_.centre_of_rotation_mm + spec_.vertex_distance_mm) / kMmPerM;

  // Cauchy: n_F - n_C = B (1 / lambda_F^2 - 1 / lambda_C^2) = (n_d - 1) / V_d, A = n_d - B / lambda_d^2.
  const auto inverse_square_um = [](double nm) { return 1.0 / ((nm * 1e-3) * (nm * 1e-3)); };
  cauchy_b_um2_ = (n - 1.0) / spec_.abbe_number_d / (inverse_square_um(kFraunhoferF_nm) - inverse_square_um(kFraunhoferC_nm));
  cauchy_a_ = n - cauchy_b_um2_ * inverse_square_um(kFraunhoferD_nm);

  const glm::dvec2 optical_centre_m = spec_.decentration_mm / kMmPerM;
  const DioptricPower prescribed = DioptricPower::from_prescription(spec_.prescription);
  const double front_curvature = front_power_dioptres_ / (n - 1.0);
  front_ = ToricSurface{front_curvature, front_curvature, glm::dvec2(1.0, 0.0), optical_centre_m};

  // Surfaces for a centre thickness t: the back toric from the thick-lens back-vertex power,
  //   F_v = F1 / (1 - (t / n) F1) + F2  (per meridian; F2 a matrix, F1 spherical),
  // and the progressive front's near-zone curvature chosen by the same formula so the near zone's
  // back-vertex power is the distance power plus the add.
  const auto build = [&](double thickness_m) {
    const double reduced = thickness_m / n;
    const double shape = 1.0 - reduced * front_power_dioptres_;
    if (!(shape > 0.0))
      refuse("the base curve " + number(front_power_dioptres_) + " D focuses inside a lens " + number(thickness_m * kMmPerM) +
             " mm thick (centre_thickness_mm or base_curve_dioptres)");
    const double front_effective = front_power_dioptres_ / shape;
    back_surface_power_ = prescribed - DioptricPower::spherical(front_effective);
    // c2 = F2 / (1 - n); the flatter principal curvature is the sweep (tyre form).
    const PrincipalPowers curvature = principal_powers(back_surface_power_ * (1.0 / (1.0 - n)));
    const double angle_rad = curvature.principal_angle_deg / kDegPerRad;
    const glm::dvec2 first(std::cos(angle_rad), std::sin(angle_rad));
    const glm::dvec2 second(-first.y, first.x);
    const bool first_flatter = std::abs(curvature.p1_dioptres) <= std::abs(curvature.p2_dioptres);
    back_ = ToricSurface{first_flatter ? curvature.p1_dioptres : curvature.p2_dioptres,
                         first_flatter ? curvature.p2_dioptres : curvature.p1_dioptres, first_flatter ? first : second,
                         optical_centre_m};
    progressive_ = ProgressiveAddition{};
    if (spec_.near_add_dioptres > 0.0) {
      const double near_effective = front_effective + spec_.near_add_dioptres;
      const double near_front = near_effective / (1.0 + reduced * near_effective);
      progressive_ = ProgressiveAddition{(near_front - front_power_dioptres_) / (n - 1.0), spec_.corridor_length_mm / kMmPerM,
                                         glm::dvec2(0.0)};
    }
  };
  // The largest S_front - S_back over the aperture: the lens is t - (S_front - S_back) thick there.
  const auto thickest_sag_difference = [&](glm::dvec2* where) {
    double largest = -1e300;
    for_each_aperture_point(radius_m, [&](glm::dvec2 at) {
      const SagSample front = front_sag(at), back = back_sag(at);
      if (!front.valid || !back.valid)
        refuse(std::string("the ") + (front.valid ? "back" : "front") + " surface curves round before the edge of diameter_mm " +
               number(spec_.diameter_mm) + " (its radius of curvature is below the lens' semi-diameter)");
      const double difference = front.sag_m - back.sag_m;
      if (difference > largest) {
        largest = difference;
        if (where) *where = at;
      }
    });
    return largest;
  };

  // Position-of-wear compensation of the near zone: the thick-lens value above is paraxial, but the
  // eye looks through the near reference point (the front surface corridor_length_mm below the
  // fitting cross) some 30 deg down, where obliquity and the sag's slope lower the pencil's power.
  // The full added curvature is therefore solved (secant) so that the traced mean power on the
  // vertex sphere along that line of sight is the distance prescription's mean plus the add, as
  // position-of-wear progressive designs are specified.
  const auto calibrate_near_zone = [&]() {
    if (!progressive_.active()) return;
    const glm::dvec2 near_point_m(0.0, -progressive_.corridor_length_m);
    const double target = spec_.prescription.sphere_dioptres + 0.5 * spec_.prescription.cylinder_dioptres + spec_.near_add_dioptres;
    const auto near_error = [&](double add_curvature) {
      progressive_.full_add_curvature_per_m = add_curvature;
      glm::dvec2 tangent = near_point_m / front_vertex_z_m();
      for (int iteration = 0; iteration < 40; ++iteration) {
        const LensRay ray = trace_from_eye(glm::dvec3(tangent, 1.0), kFraunhoferD_nm);
        if (!ray.through())
          refuse("the near reference point corridor_length_mm " + number(spec_.corridor_length_mm) +
                 " below the fitting cross cannot be seen through the lens (the line of sight " + describe(ray.outcome) + ")");
        const glm::dvec2 miss = near_point_m - glm::dvec2(ray.origin_m);
        tangent += miss / ray.origin_m.z;
        if (glm::length(miss) < 1e-12) break;
      }
      const GazePower power = lens_power_at_gaze(*this, glm::dvec3(tangent, 1.0), kFraunhoferD_nm);
      if (!power.through) refuse("the pencil through the near reference point " + std::string(describe(power.outcome)));
      return power.vertex_sphere.mean_dioptres() - target;
    };
    double a0 = progressive_.full_add_curvature_per_m, f0 = near_error(a0);
    double a1 = a0 * (1.0 - f0 / spec_.near_add_dioptres), f1 = near_error(a1);
    for (int iteration = 0; iteration < 20 && std::abs(f1) > 1e-7 && f1 != f0; ++iteration) {
      const double a2 = a1 - f1 * (a1 - a0) / (f1 - f0);
      a0 = a1;
      f0 = f1;
      a1 = a2;
      f1 = near_error(a1);
    }
    progressive_.full_add_curvature_per_m = a1;
  };

  if (spec_.centre_thickness_mm) {
    centre_thickness_m_ = *spec_.centre_thickness_mm / kMmPerM;
    const auto check_thickness = [&]() {
      glm::dvec2 where(0.0);
      minimum_thickness_m_ = centre_thickness_m_ - thickest_sag_difference(&where);
      if (!(minimum_thickness_m_ > 0.0))
        refuse("centre_thickness_mm " + number(*spec_.centre_thickness_mm) + " makes the surfaces cross: the lens would be " +
               number(minimum_thickness_m_ * kMmPerM) + " mm thick at (" + number(where.x * kMmPerM) + ", " +
               number(where.y * kMmPerM) + ") mm; it needs at least " +
               number((centre_thickness_m_ - minimum_thickness_m_) * kMmPerM) + " mm");
    };
    build(centre_thickness_m_);
    check_thickness();  // before any ray is traced through the lens
    calibrate_near_zone();
    check_thickness();  // the fitted near zone is a little steeper
  } else {
    // Fixed point: the back surface depends weakly on t through the shape factor.
    centre_thickness_m_ = kDefaultMinimumCentre_m;
    for (int iteration = 0; iteration < 8; ++iteration) {
      build(centre_thickness_m_);
      calibrate_near_zone();
      centre_thickness_m_ = std::max(kDefaultMinimumCentre_m, kDefaultMinimumEdge_m + thickest_sag_difference(nullptr));
    }
    build(centre_thickness_m_);
    calibrate_near_zone();
    minimum_thickness_m_ = centre_thickness_m_ - thickest_sag_difference(nullptr);
  }
}

double SpectacleLens::refractive_index(double wavelength_nm) const {
  const double um = wavelength_nm * 1e-3;
  return cauchy_a_ + cauchy_b_um2_ / (um * um);
}

SagSample SpectacleLens::front_sag(glm::dvec2 at_m) const {
  SagSample sphere = front_.sample(at_m);
  if (!sphere.valid || !progressive_.active()) return sphere;
  const SagSample added = progressive_.sample(at_m);
  sphere.sag_m += added.sag_m;
  sphere.gradient += added.gradient;
  return sphere;
}

SagSample SpectacleLens::back_sag(glm::dvec2 at_m) const { return back_.sample(at_m); }

LensRay SpectacleLens::trace_from_eye(glm::dvec3 gaze, double wavelength_nm) const {
  LensRay ray;
  const double n = refractive_index(wavelength_nm);
  const double radius_m = 0.5 * spec_.diameter_mm / kMmPerM;
  const glm::dvec3 direction = glm::normalize(gaze);
  const auto back = [this](glm::dvec2 at) { return back_sag(at); };
  const auto front = [this](glm::dvec2 at) { return front_sag(at); };
  const SurfaceHit first = intersect(back, back_vertex_z_m(), glm::dvec3(0.0), direction);
  if (!first.hit) return {LensRayOutcome::misses_back_surface};
  if (glm::length(glm::dvec2(first.point_m)) > radius_m) return {LensRayOutcome::outside_aperture};
  glm::dvec3 inside;
  if (!refract(direction, first.normal, 1.0, n, inside)) return {LensRayOutcome::total_internal_reflection};
  const SurfaceHit second = intersect(front, front_vertex_z_m(), first.point_m, inside);
  if (!second.hit) return {LensRayOutcome::misses_front_surface};
  if (glm::length(glm::dvec2(second.point_m)) > radius_m) return {LensRayOutcome::outside_aperture};
  if (!refract(inside, second.normal, n, 1.0, ray.direction)) return {LensRayOutcome::total_internal_reflection};
  ray.origin_m = second.point_m;
  return ray;
}

LensRay SpectacleLens::trace_from_scene(glm::dvec3 origin_m, glm::dvec3 direction, double wavelength_nm) const {
  LensRay ray;
  const double n = refractive_index(wavelength_nm);
  const double radius_m = 0.5 * spec_.diameter_mm / kMmPerM;
  const glm::dvec3 unit = glm::normalize(direction);
  const auto back = [this](glm::dvec2 at) { return back_sag(at); };
  const auto front = [this](glm::dvec2 at) { return front_sag(at); };
  const SurfaceHit first = intersect(front, front_vertex_z_m(), origin_m, unit);
  if (!first.hit) return {LensRayOutcome::misses_front_surface};
  if (glm::length(glm::dvec2(first.point_m)) > radius_m) return {LensRayOutcome::outside_aperture};
  glm::dvec3 inside;
  if (!refract(unit, first.normal, 1.0, n, inside)) return {LensRayOutcome::total_internal_reflection};
  const SurfaceHit second = intersect(back, back_vertex_z_m(), first.point_m, inside);
  if (!second.hit) return {LensRayOutcome::misses_back_surface};
  if (glm::length(glm::dvec2(second.point_m)) > radius_m) return {LensRayOutcome::outside_aperture};
  if (!refract(inside, second.normal, n, 1.0, ray.direction)) return {LensRayOutcome::total_internal_reflection};
  ray.origin_m = second.point_m;
  return ray;
}

}  // namespace glarelab

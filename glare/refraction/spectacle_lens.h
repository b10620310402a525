#pragma once
// A spectacle lens as a real, thick lens for ray tracing: a spherical front (base) curve, a toric
// back surface that makes the back-vertex power the prescription, optional decentration and
// progressive addition, and the glass' dispersion (docs/SPECTACLES.md).
//
// Lens frame: origin at the eye's centre of rotation, x to the observer's right, y up, z forward
// along the primary line of sight (straight ahead) toward the scene; metres. The cornea is at
// z = centre_of_rotation_mm, the back vertex vertex_distance_mm further, the front vertex a centre
// thickness beyond it. Rays are traced from the eye outward (Snell's law is reversible): a gaze
// direction from the centre of rotation through the lens into the scene, as in Kakimoto et al. 2007,
// section 4.2, where the double-refracted ray from the viewpoint stands for the light path.
#include <optional>
#include <string>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "glare/refraction/dioptric_power.h"
#include "glare/refraction/spectacle_surface.h"

namespace glarelab {

// The Fraunhofer lines that define the Abbe number (nm): C (hydrogen), d (helium), F (hydrogen).
inline constexpr double kFraunhoferC_nm = 656.27;
inline constexpr double kFraunhoferD_nm = 587.56;
inline constexpr double kFraunhoferF_nm = 486.13;

struct SpectacleLensSpec {
  // The back-vertex power at the d line, minus-cylinder form, TABO axis (glare/refraction/dioptric_power.h).
  SpheroCylinder prescription;
  double refractive_index_d = 1.498;  // CR-39 (allyl diglycol carbonate), the common plastic
  double abbe_number_d = 58.0;        // CR-39
  double vertex_distance_mm = 12.0;   // back vertex to corneal vertex
  // Unset: the thinnest lens with at least 2.0 mm at the centre and 1.0 mm at the thinnest point
  // of the edge (figures of common uncoated CR-39 lenses).
  std::optional<double> centre_thickness_mm;
  double diameter_mm = 50.0;  // the round aperture, centred on the primary line of sight
  // The optical centre's offset from the primary line of sight, observer frame (x right, y up), mm.
  glm::dvec2 decentration_mm{0.0};
  // Front-surface power at the d line. Unset: Vogel's rule on the spherical equivalent S + C/2,
  // S + C/2 + 6 D for plus lenses and (S + C/2) / 2 + 6 D for minus lenses.
  std::optional<double> base_curve_dioptres;
  // Progressive addition (0: single vision): the back-vertex add reached at corridor_length_mm below
  // the fitting cross, which sits on the primary line of sight (glare/refraction/spectacle_surface.h).
  double near_add_dioptres = 0.0;
  double corridor_length_mm = 14.0;
  double centre_of_rotation_mm = 13.5;  // corneal vertex to the eye's centre of rotation
};

// Why a ray did not come through the lens.
enum class LensRayOutcome { through, misses_back_surface, misses_front_surface, outside_aperture, total_internal_reflection };
const char* describe(LensRayOutcome outcome);

// A ray after the lens: where it leaves the last surface and its unit direction.
struct LensRay {
  LensRayOutcome outcome = LensRayOutcome::through;
  glm::dvec3 origin_m{0.0};
  glm::dvec3 direction{0.0, 0.0, 1.0};
  bool through() const { return outcome == LensRayOutcome::through; }
};

class SpectacleLens {
 public:
  // Builds the lens; throws std::invalid_argument naming the parameter ("glare/refraction/spectacle_lens: ...")
  // for an index <= 1, an Abbe number <= 0, an axis outside [0, 180], a vertex distance, diameter,
  // corridor length or centre of rotation <= 0, a thickness that leaves the lens no edge, or
  // surfaces that do not reach across the diameter.
  explicit SpectacleLens(const SpectacleLensSpec& spec);

  const SpectacleLensSpec& spec() const { return spec_; }

  // Cauchy's two-term dispersion formula n(lambda) = A + B / lambda^2 through n_d at the d line and
  // n_F - n_C = (n_d - 1) / V_d (the Abbe number's definition).
  double refractive_index(double wavelength_nm) const;

  double front_power_dioptres() const { return front_power_dioptres_; }  // base curve, at n_d
  // Back-surface power matrix at n_d (observer frame): prescription - F1 / (1 - (t / n_d) F1).
  const DioptricPower& back_surface_power() const { return back_surface_power_; }
  double centre_thickness_m() const { return centre_thickness_m_; }
  // The thinnest point over the aperture (the centre of a minus lens, the edge of a plus lens).
  double minimum_thickness_m() const { return minimum_thickness_m_; }
  double back_vertex_z_m() const { return back_vertex_z_m_; }
  double front_vertex_z_m() const { return back_vertex_z_m_ + centre_thickness_m_; }
  double cornea_z_m() const { return spec_.centre_of_rotation_mm * 1e-3; }
  // Radius of the vertex sphere (centred on the centre of rotation, through the back vertex), where
  // lens power is measured for every gaze direction.
  double vertex_sphere_radius_m() const { return back_vertex_z_m_; }
  const ToricSurface& front_sphere() const { return front_; }
  const ToricSurface& back_toric() const { return back_; }
  const ProgressiveAddition& progressive() const { return progressive_; }

  // Sag of the front and back surfaces (front includes the progressive addition).
  SagSample front_sag(glm::dvec2 at_m) const;
  SagSample back_sag(glm::dvec2 at_m) const;

  // The ray the eye sends from its centre of rotation along `gaze` (need not be unit; z > 0)
  // through the back then the front surface, at the given wavelength: its origin on the front
  // surface and its direction in the scene.
  LensRay trace_from_eye(glm::dvec3 gaze, double wavelength_nm) const;
  // A ray arriving from the scene side (origin in front of the lens, direction with z < 0) through
  // the front then the back surface: where it leaves the back surface and its direction.
  LensRay trace_from_scene(glm::dvec3 origin_m, glm::dvec3 direction, double wavelength_nm) const;

 private:
  SpectacleLensSpec spec_;
  double front_power_dioptres_ = 0.0;
  DioptricPower back_surface_power_;
  double centre_thickness_m_ = 0.0;
  double minimum_thickness_m_ = 0.0;
  double back_vertex_z_m_ = 0.0;
  double cauchy_a_ = 0.0;
  double cauchy_b_um2_ = 0.0;
  ToricSurface front_;
  ToricSurface back_;
  ProgressiveAddition progressive_;
};

}  // namespace glarelab

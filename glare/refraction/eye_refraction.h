#pragma once
// The observer's refraction: Kakimoto, Tatsukawa, Mukai and Nishita, "Interactive Simulation of the
// Human Eye Depth of Field and Its Correction by Spectacle Lenses", Eurographics 2007, section 4.4:
// the eye as a thin toric lens at the cornea on the Gullstrand-Helmholtz schematic eye (Table 2),
// accommodating to put the circle of least confusion on the retina (Eqs. 10-13), its astigmatism
// split about the mean power (Eqs. 14-15). Powers are dioptric power matrices in the observer frame
// (glare/refraction/dioptric_power.h: x to the observer's right, y up; TABO axes mapped there), so Kakimoto's
// directional powers P_x, P_y, P_xy (Eq. 3) are the matrix's entries and his vergence formula (Eq. 7)
// is a matrix sum.
//
// Quantities (all dioptres, 1/m, or metres):
//   K   the ocular refraction: the vergence at the cornea that the relaxed eye focuses on the retina,
//       the clinical correcting prescription (sphere, minus cylinder, TABO axis) written at its vertex
//       distance and moved to the cornea (effective_power_at_distance; K = Rx / (1 - d Rx) for a
//       sphere).
//   P   the eye's power. Relaxed: P_min = (n2 / z_r) I - K, so that K + P_min = n2 / z_r, the
//       vergence that converges on the retina (Eq. 11). Its principal powers are Kakimoto's
//       P_1,min and P_2,min about the mean P-bar_min (Eq. 14), the astigmatism A = P_1,min - P_2,min.
//       Accommodated: P = P_min + Delta P I (Eq. 15).
//   V   the vergence at the cornea of the light from a point (-1 / distance for a point in front of
//       the naked eye; through spectacles, the lens' vergence carried to the cornea, Eq. 1).
//   E   the residual power error at the retina: E = V + P - (n2 / z_r) I = V - K + Delta P I.
//       Positive: too much power (the light focuses in front of the retina, as in a myope looking far).
//       geometric_blur_ellipse(E, pupil radius) is the blur in visual angle, and
//       ApertureGeometry::refraction_error takes E for the wave-optics PSF.
//
// Accommodation (Eq. 13): Delta P = clamp(n2 / z_r - kappa-bar - P-bar_min, 0, amplitude), kappa-bar
// the mean vergence at the cornea of the fixated point; with P-bar_min = n2 / z_r - mean(K) this is
// clamp(mean(K) - mean(V_fixation), 0, amplitude): the mean residual at fixation is zero whenever the
// amplitude allows, and the astigmatic residual is split +-A/2 about it (the circle of least
// confusion on the retina, Eq. 10).
#include <limits>
#include <optional>

#include "glare/refraction/dioptric_power.h"

namespace glarelab {

// Kakimoto et al. 2007, Table 2 (Gullstrand and Helmholtz's schematic eye).
inline constexpr double kSchematicRelaxedPowerDioptres = 58.64;          // P-bar_min, minimal accommodation
inline constexpr double kSchematicAccommodationAmplitudeDioptres = 11.93;  // Delta_max
inline constexpr double kSchematicCorneaRetina_m = 22.785e-3;            // z_r, front cornea to retina
inline constexpr double kAirIndex = 1.000;                               // n1
inline constexpr double kVitreousIndex = 1.336;                          // n2
// Spectacle vertex distance assumed when a prescription names none (the usual 12 mm).
inline constexpr double kDefaultVertexDistance_m = 12e-3;

// n2 / z_r = 58.635 D: the power of the emmetropic schematic eye, which Table 2 rounds to 58.64 D.
// The emmetrope is defined by this value (not by 58.64) so that it has no residual at infinity; the
// 0.005 D between the two is Table 2's rounding.
double emmetropic_power_dioptres();

// Amplitude of accommodation by age: Hofstetter's average, 18.5 - 0.3 age dioptres (H. W. Hofstetter,
// "A useful age-amplitude formula", Optometry World 38:42-45, 1950), floored at 0 (no amplitude
// from 61.7 years). Throws std::invalid_argument (naming "glare/refraction/eye_refraction") for a negative or
// non-finite age.
double hofstetter_amplitude_dioptres(double age_years);

// A sphero-cylindrical lens worn at vertex_distance_m in front of the cornea, as a thin lens: its
// power only. The real lens, traced ray by ray (thickness, index, dispersion, prism, progressive
// add), is glare/refraction/spectacle_lens.h.
struct ThinSpectacleLens {
  SpheroCylinder prescription;
  double vertex_distance_m = kDefaultVertexDistance_m;
};

struct EyeRefraction {
  // The eye's error written as its correcting prescription (minus cylinder, TABO axis), measured at
  // prescription_vertex_distance_m in front of the cornea. Zero: an emmetrope.
  SpheroCylinder correcting_prescription;
  double prescription_vertex_distance_m = kDefaultVertexDistance_m;
  double accommodation_amplitude_dioptres = kSchematicAccommodationAmplitudeDioptres;  // Delta_max, >= 0
};

// The relaxed eye's principal powers (Eq. 14) and the direction of P_1 (the stronger meridian), in
// degrees from +x, counterclockwise in the observer frame ([0, 180)).
struct EyePrincipalPowers {
  double p1_min_dioptres = 0.0;
  double p2_min_dioptres = 0.0;
  double mean_dioptres = 0.0;        // P-bar_min
  double astigmatism_dioptres = 0.0;  // A = P_1,min - P_2,min >= 0
  double p1_direction_deg = 0.0;     // Kakimoto's omega_1^(e), measured in the observer frame
};

class RefractiveEye {
 public:
  // Throws std::invalid_argument (naming "glare/refraction/eye_refraction") for a negative or non-finite
  // amplitude or vertex distance, and when the prescription focuses at the cornea.
  explicit RefractiveEye(const EyeRefraction& refraction);

  const EyeRefraction& refraction() const { return refraction_; }
  // K: the prescription moved from its vertex distance to the cornea.
  const DioptricPower& ocular_refraction() const { return ocular_refraction_; }
  // P_min = (n2 / z_r) I - K, and its principal powers (Eq. 14).
  DioptricPower relaxed_power() const;
  EyePrincipalPowers relaxed_principal_powers() const;
  // Eq. 13: the accommodation (dioptres, in [0, amplitude]) for a fixated point whose light reaches
  // the cornea with mean vergence mean_vergence_dioptres (kappa-bar).
  double accommodation_dioptres(double mean_vergence_dioptres) const;
  // Eq. 15: P = P_min + Delta P I.
  DioptricPower power(double accommodation_dioptres) const;
  // E = V + P - (n2 / z_r) I for light of vergence V at the cornea, with the eye accommodated by
  // accommodation_dioptres.
  DioptricPower residual_error(const DioptricPower& vergence_at_cornea, double accommodation_dioptres) const;

 private:
  EyeRefraction refraction_;
  DioptricPower ocular_refraction_;
};

// The vergence at the cornea of the light from a point object_distance_m in front of the cornea
// (infinity: a distant point). Naked eye: -1 / distance. Through spectacles: -1 / (distance - d) at
// the lens, plus the lens, carried the vertex distance d to the cornea (Eq. 1, as
// effective_power_at_distance). Throws std::invalid_argument (naming "glare/refraction/eye_refraction") for a
// distance not beyond the lens (or not positive), and when the light focuses at the cornea.
DioptricPower vergence_at_cornea(double object_distance_m, const std::optional<ThinSpectacleLens>& spectacles);

// What the observer looks at and through.
struct ViewingCondition {
  double fixation_distance_m = std::numeric_limits<double>::infinity();  // from the cornea
  std::optional<ThinSpectacleLens> spectacles;
};

struct FixationRefraction {
  DioptricPower fixation_vergence;    // V of the fixated point at the cornea
  double accommodation_dioptres = 0.0;  // Delta P chosen for it (Eq. 13)
  DioptricPower residual;             // E at the fixated point
};
FixationRefraction refraction_at_fixation(const RefractiveEye& eye, const ViewingCondition& viewing);

// The residual error E for a point at object_distance_m while the eye keeps the accommodation chosen
// for viewing.fixation_distance_m (depth of field: a point off the fixation distance blurs).
DioptricPower residual_error_at(const RefractiveEye& eye, const ViewingCondition& viewing, double object_distance_m);

// Kakimoto's Sturm-conoid section at the retina (Eq. 8), from the refracted wavefront's principal
// curvatures kappa'_1 >= kappa'_2 (Eqs. 5 and 7: kappa' = mu kappa + P / n2, with n1 = 1 so
// kappa = V): a = r_p (1 - kappa'_1 z_r), b = r_p (1 - kappa'_2 z_r), signed lengths (metres) on the
// retina along the principal directions; first_direction_deg is that of kappa'_1 (observer frame).
struct SturmSection {
  double a_m = 0.0;
  double b_m = 0.0;
  double first_direction_deg = 0.0;
};
SturmSection sturm_conoid_section(const RefractiveEye& eye, const DioptricPower& vergence_at_cornea,
                                  double accommodation_dioptres, double pupil_radius_m);

}  // namespace glarelab

#pragma once
// Sphero-cylindrical powers (a prescription, a spectacle lens, an eye's refractive error) as
// dioptric power matrices (Harris, "Dioptric power: its nature and its representation in three-
// and four-dimensional space", Optom. Vis. Sci. 74, 1997): a symmetric 2 x 2 matrix F whose
// quadratic form gives the power in every meridian, so powers at any axes add as matrices, the
// way Kakimoto et al. 2007 (Eqs. 3, 7) add directional curvatures and powers.
//
// Frame: the observer's visual field as the observer sees it, x to the observer's right, y up
// (the convention of every PSF image here, whose row 0 is at the top). Lengths in metres, powers
// in dioptres (1/m).
//
// Prescriptions are written as clinics write them: sphere S, cylinder C and axis theta in TABO
// degrees [0, 180), the angle of the cylinder axis measured counterclockwise from the horizontal as
// the examiner, facing the patient, sees it, 0 on the examiner's right. The examiner's view is the
// observer's mirrored left-right, so in this frame the axis is the line at alpha = 180 - theta
// degrees from +x (a TABO 45 axis runs up and to the observer's left). The power is S along the
// axis meridian and S + C across it:
//   F = S I + C n n^T,  n = (-sin alpha, cos alpha) the unit normal to the axis.
// Minus-cylinder form (C <= 0) is what glarelab writes; a plus-cylinder prescription transposes
// to (S + C, -C, theta + 90) (the same lens).
#include <glm/mat2x2.hpp>
#include <glm/vec2.hpp>

#include "core/observer_optics.h"  // SpheroCylinder

namespace glarelab {

// A symmetric dioptric power matrix in the observer frame above (glm is column-major; the matrix is
// symmetric, so F[0][1] == F[1][0] is the xy term either way).
struct DioptricPower {
  glm::dmat2 matrix_dioptres{0.0};

  static DioptricPower spherical(double power_dioptres);
  static DioptricPower from_prescription(const SpheroCylinder& prescription);

  double xx() const { return matrix_dioptres[0][0]; }
  double xy() const { return matrix_dioptres[1][0]; }
  double yy() const { return matrix_dioptres[1][1]; }
  // Mean spherical equivalent, (P1 + P2) / 2 = trace / 2 (Kakimoto's P-bar, Eq. 11).
  double mean_dioptres() const { return 0.5 * (xx() + yy()); }
  // Power in the meridian at angle_deg from +x (Euler's formula, Kakimoto Eq. 3).
  double meridian_dioptres(double angle_deg) const;

  // The same power written as a minus-cylinder prescription (axis TABO in [0, 180)). A spherical
  // power has cylinder 0 and axis 0.
  SpheroCylinder prescription() const;

  DioptricPower operator+(const DioptricPower& other) const { return {matrix_dioptres + other.matrix_dioptres}; }
  DioptricPower operator-(const DioptricPower& other) const { return {matrix_dioptres - other.matrix_dioptres}; }
  DioptricPower operator*(double factor) const { return {matrix_dioptres * factor}; }
};

// Principal powers and directions: P1 >= P2, principal_angle_deg the direction (in [0, 180), from
// +x, counterclockwise in the observer frame) of the meridian whose power is P1.
struct PrincipalPowers {
  double p1_dioptres = 0.0;
  double p2_dioptres = 0.0;
  double principal_angle_deg = 0.0;
};
PrincipalPowers principal_powers(const DioptricPower& power);

// Converts TABO degrees (examiner's view) to the observer-frame axis angle alpha, and back.
double observer_axis_deg_from_tabo(double tabo_deg);
double tabo_from_observer_axis_deg(double observer_axis_deg);

// A thin lens' power moved along the axis by distance_m toward the eye (vertex-distance
// compensation): F_eff = F (I - d F)^-1 (Harris 1997; for a sphere, F / (1 - d F)). Throws
// std::invalid_argument (naming "glare/refraction/dioptric_power") when I - d F is singular, i.e. the lens
// focuses at the new plane.
DioptricPower effective_power_at_distance(const DioptricPower& power, double distance_m);

// The geometric blur of a power error E over a circular pupil of radius r: the ray through pupil
// point p leaves at angle E p (radians, small angles), so the blur is the pupil disc mapped by E: an
// ellipse with semi-axes |lambda_i| r along E's eigenvectors. This is Kakimoto's Sturm-conoid section
// (Eq. 8) written in angle instead of length at the retina.
struct BlurEllipse {
  double semi_major_rad = 0.0;
  double semi_minor_rad = 0.0;
  double major_axis_angle_deg = 0.0;  // direction of the major semi-axis, [0, 180), observer frame
};
BlurEllipse geometric_blur_ellipse(const DioptricPower& error, double pupil_radius_m);

}  // namespace glarelab

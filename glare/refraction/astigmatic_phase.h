#pragma once
// The pupil phase of a sphero-cylindrical power error (defocus and astigmatism at any axis), the
// generalisation of the quadratic defocus phase of glare/wave/fresnel.h. A power error E (a dioptric power
// matrix, glare/refraction/dioptric_power.h) bends the ray through pupil point p by E p, which is the gradient
// of the wavefront W(p) = p^T E p / 2; the phase is 2 pi W / lambda:
//   phi(x, y) = (pi / lambda) (E_xx x^2 + 2 E_xy x y + E_yy y^2).
// For E = D I it is exactly glare/wave/fresnel.h's pi (D / lambda) r^2. With an oblique axis the xy term does
// not separate into a row factor times a column factor.
#include <complex>
#include <vector>

#include "glare/eye/aperture_raster.h"
#include "glare/refraction/dioptric_power.h"
#include "glare/wave/fresnel.h"

namespace glarelab {

// Phase (radians) at pupil point (x_m, y_m), metres in the observer frame (x right, y up).
double power_error_phase_rad(const DioptricPower& error, double wavelength_nm, double x_m, double y_m);

// The complex aperture A exp(i phi) at the pixel centres of `grid` (glare/eye/aperture_raster.h's coordinates).
std::vector<std::complex<double>> apply_power_error_phase(const ApertureGrid& grid, const DioptricPower& error,
                                                          double wavelength_nm);

// Sampling check for phi: its gradient (2 pi / lambda) E p is largest at the pupil edge along the
// principal meridian of largest |power|, where it equals that of a spherical defocus of that power;
// the check is glare/wave/fresnel.h's with c = max |P_i| / lambda.
PhaseSamplingReport check_power_error_sampling(const DioptricPower& error, double wavelength_nm, double pupil_radius_mm,
                                               double pixel_mm, double aperture_width_mm);

}  // namespace glarelab

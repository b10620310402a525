#pragma once
// Radial lens-fibre gratings in an annulus of the lens cortex: opaque-ish radial lines whose
// tangential spacing is the fibre period. Diffraction at such a grating sends light to the angle
// sin(theta) = lambda / period perpendicular to the lines, i.e. a ring: the lenticular halo.
// Spencer et al. 1995, section 3.1.1 (after Simpson): the halo lies at about 3 degrees for 568 nm,
// so the period is 568 nm / sin(3 deg) = 10.85 um. Lens fibres keep their width as the lens grows
// (cell columns branch), so the period is held constant over the annulus: the annulus is split into
// rings narrow enough (outer / inner radius <= 1.05) that the spacing of the radial lines in each
// stays within 2.5% of the period.
#include "glare/eye/aperture_geometry.h"

namespace glarelab {

// Period (micrometres) that puts the first-order halo at halo_degrees for wavelength_nm.
double grating_period_um(double wavelength_nm, double halo_degrees);

struct FibreGratingOptions {
  double inner_radius_mm = 1.5;
  double outer_radius_mm = 2.5;
  double period_um = 10.85;       // grating_period_um(568, 3.0)
  double duty = 0.5;              // line width / period
  double transmittance = 0.0;     // of a fibre boundary line
};

// Appends the lines to geometry.lines.
void add_radial_fibre_gratings(ApertureGeometry& geometry, const FibreGratingOptions& options);

}  // namespace glarelab

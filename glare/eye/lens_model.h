#pragma once
// The crystalline lens (Ritschel et al. 2009, section 3.3): scattering particles that move with the
// lens as accommodation deforms it, and the fibre gratings of the cortex that cause the lenticular halo.
//
// Deformation: a uniform 17 x 17 mass-spring grid over the lens's meridional half-section (radius
// r in [0, R], depth z in [-T/2, T/2]), with structural and shear springs of one stiffness, the axis
// held radially (symmetry) and a single element, the equatorial node where the ciliary muscle pulls,
// moved by the accommodation signal (Ritschel Fig. 4). The driver is slow (< 2.1 Hz) against the
// grid's natural frequencies, so the grid is in equilibrium at every instant; for the micrometre
// displacements of microfluctuations the springs are linear, so the equilibrium is the driver
// displacement times one unit response, solved once (conjugate gradients on the stiffness matrix).
// Particles look the deformation up by bilinear interpolation of the grid and are mapped from
// cylindrical (r, phi) to the pupil plane.
#include <cstdint>
#include <vector>

#include "glare/eye/aperture_geometry.h"
#include "glare/eye/eye_parameters.h"

namespace glarelab {

class LensDeformation {
 public:
  explicit LensDeformation(const EyeParameters& parameters);

  struct Displacement {
    double radial_mm = 0.0;
    double axial_mm = 0.0;
  };
  // Bilinear interpolation of the grid's equilibrium for an equator displacement (radial, mm).
  Displacement displacement(double r_mm, double z_mm, double equator_displacement_mm) const;
  // The unit response at grid node (i: radial index, j: axial index).
  Displacement node_unit_response(int i, int j) const;
  int nodes_per_side() const { return nodes_; }
  int driver_axial_index() const { return nodes_ / 2; }
  // Largest |K u - f| over free degrees of freedom after the solve (equilibrium check).
  double residual() const { return residual_; }

 private:
  int nodes_;
  double radius_mm_, half_thickness_mm_;
  std::vector<double> unit_radial_, unit_axial_;  // per node, index i * nodes + j
  double residual_ = 0.0;
};

struct LensParticle {
  double r_mm;        // radius in the meridional section (rest shape)
  double z_mm;        // depth in the lens, 0 at the equatorial plane
  double angle_rad;   // angle about the optical axis
  double diameter_mm;
};

class LensModel {
 public:
  LensModel(const EyeParameters& parameters, std::uint64_t seed);

  const std::vector<LensParticle>& particles() const { return particles_; }
  const std::vector<ApertureLine>& grating_lines() const { return grating_lines_; }
  const LensDeformation& deformation() const { return deformation_; }

  // Radial equator displacement (mm) for an accommodation fluctuation about the demand (dioptres):
  // the lens rounds up, its equator moving inwards, as accommodation rises.
  double equator_displacement_mm(double accommodation_fluctuation_dioptres) const;
  // The particles, deformed, projected orthographically onto the pupil plane (opaque discs).
  void append_particles(double equator_displacement_mm, std::vector<ApertureDisc>& discs) const;
  // False when no grating line reaches into a pupil of this diameter (the iris hides the cortex).
  bool gratings_visible(double pupil_diameter_mm) const;

 private:
  EyeParameters parameters_;
  LensDeformation deformation_;
  std::vector<LensParticle> particles_;
  std::vector<ApertureLine> grating_lines_;
  double grating_min_reach_mm_ = 0.0;  // smallest distance of any grating line's edge to the axis
};

}  // namespace glarelab

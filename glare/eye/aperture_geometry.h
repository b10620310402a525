#pragma once
// The eye's aperture at one instant, as geometry in the pupil plane: lengths in millimetres,
// origin on the optical axis, x to the observer's right, y up, seen from the front (the light's
// side). The eye model (glare/eye/eye_model.h) produces it; the CPU rasteriser and the GPU both draw it with
// the same coverage rule (glare/eye/aperture_raster.h), so the two compute backends see the same aperture.
//
// Transmittance composes multiplicatively (Ritschel et al. 2009, section 4: every part of the eye
// attenuates what passes through it): at a point p,
//   A(p) = [|p| <= pupil_diameter_mm / 2] * prod over primitives containing p of transmittance.
#include <cstdint>
#include <vector>

#include "glare/refraction/dioptric_power.h"

namespace glarelab {

// The part of the eye a primitive stands for (Ritschel et al. 2009, Table 1), so a PSF can be
// computed from chosen parts only (`glarelab psf --components`). 64-bit so the primitives have no
// padding bytes and compare bytewise. Hand-made geometry may leave it unspecified.
enum class ApertureComponent : std::uint64_t { unspecified, lens, gratings, vitreous, cornea, retina, lids, lashes };

struct ApertureDisc {  // lens, cornea, vitreous and retina particles
  double centre_x_mm = 0.0;
  double centre_y_mm = 0.0;
  double radius_mm = 0.0;
  double transmittance = 0.0;  // 0 = opaque
  ApertureComponent component = ApertureComponent::unspecified;
};

struct ApertureLine {  // lens fibres (gratings), eyelashes: a segment with a width
  double x0_mm = 0.0, y0_mm = 0.0;
  double x1_mm = 0.0, y1_mm = 0.0;
  double width_mm = 0.0;
  double transmittance = 0.0;
  ApertureComponent component = ApertureComponent::unspecified;
};

struct AperturePolygon {  // eyelids: a simple polygon (convex or not, even-odd rule)
  std::vector<double> vertices_mm;  // x0, y0, x1, y1, ...
  double transmittance = 0.0;
  ApertureComponent component = ApertureComponent::unspecified;
};

struct ApertureGeometry {
  double pupil_diameter_mm = 4.0;
  std::vector<ApertureDisc> discs;
  std::vector<ApertureLine> lines;
  std::vector<AperturePolygon> polygons;
  // Defocus of the eye (accommodation error), in dioptres; gives the quadratic phase
  // phi(r) = pi * defocus_dioptres * r^2 / lambda of a thin-lens focus error.
  double defocus_dioptres = 0.0;
  // The observer's residual sphero-cylindrical error (the refraction left after accommodation and
  // any spectacles; glare/refraction/dioptric_power.h), added to defocus_dioptres: the pupil phase is that of
  // E = defocus_dioptres I + refraction_error (glare/refraction/astigmatic_phase.h). Zero for an emmetrope.
  DioptricPower refraction_error;
  DioptricPower total_power_error() const { return DioptricPower::spherical(defocus_dioptres) + refraction_error; }
  // True when the phase does not reduce to glare/wave/fresnel.h's rotationally symmetric pi D r^2 / lambda.
  bool astigmatic() const {
    return refraction_error.xy() != 0.0 || refraction_error.xx() != refraction_error.yy();
  }
  // False for the "control" condition (no glare): the consumer passes the image through unchanged
  // and ignores everything else here (the eye model then sends the pupil only, no scatterers).
  bool glare_enabled = true;
};

}  // namespace glarelab

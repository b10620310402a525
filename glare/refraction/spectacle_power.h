#pragma once
// The power of a spectacle lens along each line of sight, as a blur stage needs it: the vergence
// of the thin pencil that a distant point sends through the lens around the chief ray to the eye's
// centre of rotation, as a dioptric power matrix (glare/refraction/dioptric_power.h) in the rotated eye's
// frame. It includes the oblique astigmatism of the gaze through the lens, the prism's own
// astigmatism and, in a progressive lens, the add and the surface astigmatism beside the corridor.
//
// Method: finite differences of neighbouring rays. Four rays parallel to the chief ray's direction
// in the scene, offset by +-h in two directions across it, are traced through the real surfaces
// (glare/refraction/spectacle_lens.h) to the plane across the chief ray at the vertex sphere; there the ray
// slopes s and positions p across the chief ray give the vergence V = -(ds/da) (dp/da)^-1 (central
// differences, h = 0.02 mm: the truncation error is of order (h / r)^2 ~ 1e-7 of the power for
// surface radii r of tens of mm, far below the 0.01 D of a focimeter). Kakimoto et al.'s wavefront
// tracing (Eqs. 1-5) gives the same pencil for smooth surfaces but needs each surface's curvature
// tensor at the hit point; finite differences use the very rays the image warp uses, so the power
// and the warp cannot disagree, and the progressive surface needs no second derivatives.
//
// Frame: the eye rotated to the gaze by Listing's law (about the axis perpendicular to both the
// primary line of sight and the gaze), taking the observer frame (x right, y up) with it; for the
// primary gaze it is the observer frame itself.
#include <glm/mat2x2.hpp>
#include <glm/vec3.hpp>

#include "glare/refraction/dioptric_power.h"
#include "glare/refraction/spectacle_lens.h"

namespace glarelab {

struct GazePower {
  bool through = false;               // false: the gaze misses the lens (`outcome` says how)
  LensRayOutcome outcome = LensRayOutcome::through;
  glm::dvec3 scene_direction{0.0};    // where the chief ray goes in the scene (unit)
  // The lens' power for a distant object at the vertex sphere (centre of rotation to back vertex):
  // the prescription, on the primary line of sight through an undecentred single-vision lens.
  DioptricPower vertex_sphere;
  // The same pencil's vergence at the corneal vertex of the rotated eye, vertex_distance_mm nearer
  // (effective_power_at_distance): what the eye's own refraction meets.
  DioptricPower at_cornea;
  // How the scene's angles change with the eye's: d(scene angle) / d(visual angle), the scene angles
  // across the chief ray's scene direction in its own Listing frame, the visual ones in the eye's
  // (columns: per visual angle along the eye's x', y'). The inverse of the local spectacle
  // magnification: (1 - (t / n) F1) (I - h F_v) paraxially on the primary line of sight, h the back
  // vertex's distance from the centre of rotation. This is the lens' part of Kakimoto et al.'s
  // scaling factors s_h, s_v (Eq. 9, Fig. 9), there with a thin lens, here from the traced rays.
  glm::dmat2 scene_per_visual_angle{1.0};
};

// The eye's frame for a gaze direction (Listing's law), columns x', y', z' = gaze.
struct ListingFrame {
  glm::dvec3 right{1.0, 0.0, 0.0};
  glm::dvec3 up{0.0, 1.0, 0.0};
  glm::dvec3 gaze{0.0, 0.0, 1.0};
};
ListingFrame listing_eye_frame(glm::dvec3 gaze);

// The lens' power along `gaze` (from the centre of rotation, z > 0) at the given wavelength.
GazePower lens_power_at_gaze(const SpectacleLens& lens, glm::dvec3 gaze, double wavelength_nm);

}  // namespace glarelab

#pragma once
// The refracting surfaces of a spectacle lens as sag functions (glare/refraction/spectacle_lens.h).
//
// A surface is z = vertex_z - S(x, y) in the lens frame (x right, y up, z forward toward the
// object, metres), so S is measured from the vertex plane toward the eye, the direction light from
// the scene travels. Curvatures follow the optics sign convention for that direction: positive when
// the centre of curvature lies on the eye's side, so a surface's power is (n' - n) c (a front
// surface convex to the scene has c > 0 and power (n - 1) c; the back surface, (1 - n) c).
#include <glm/vec2.hpp>

namespace glarelab {

// Sag and its gradient at one point of a surface; `valid` is false where the point lies outside
// the surface's domain (a circle's sag beyond its radius).
struct SagSample {
  double sag_m = 0.0;
  glm::dvec2 gradient{0.0};  // (dS/dx, dS/dy), dimensionless
  bool valid = false;
};

// A toric surface in tyre form: the circle of the tube curvature (across the sweep meridian) swept
// around an axis parallel to the tube's plane at the sweep radius. With both curvatures equal it is
// a sphere; with one of them zero, a cylinder. In curvature form, with u along `sweep_direction` and
// v across it (local coordinates about `centre_m`):
//   S_v = c_t v^2 / (1 + sqrt(1 - c_t^2 v^2)),   c_u' = c_s / (1 - c_s S_v),
//   S   = S_v + c_u' u^2 / (1 + sqrt(1 - c_u'^2 u^2)),
// every section v = const being a circle centred on the sweep axis (the torus' exact sag; the
// tyre form keeps the flatter curvature as the sweep so the sweep radius exceeds the tube's).
struct ToricSurface {
  double sweep_curvature_per_m = 0.0;
  double tube_curvature_per_m = 0.0;
  glm::dvec2 sweep_direction{1.0, 0.0};  // unit, lens frame
  glm::dvec2 centre_m{0.0};              // where the vertex lies (the optical centre)

  SagSample sample(glm::dvec2 at_m) const;
};

// The progressive addition of the front surface: zero at and above the fitting cross, then along
// the corridor (the vertical line through the fitting cross) an added curvature a(s) rising with
// the distance s below the cross as a quintic smootherstep, a(s) = a_full E(s / L),
// E(x) = 10 x^3 - 15 x^4 + 6 x^5 (C2: the power and its first two derivatives are continuous), full
// from s = L (the corridor length, at the near reference point) down. The added sag is
//   dS(x, y) = g(s) + a(s) x^2 / 2,   g'' = a,  g(0) = g'(0) = 0,
// so on the corridor line the surface stays umbilic (equal added curvature a along and across it)
// and off it the twist term a'(s) x brings the surface astigmatism 2 |a'(s)| |x| that Minkwitz's
// theorem requires beside an umbilic line whose curvature changes (Minkwitz 1963, Optica Acta 10,
// 223-227: astigmatism grows across the line at twice the rate the power grows along it).
struct ProgressiveAddition {
  double full_add_curvature_per_m = 0.0;
  double corridor_length_m = 0.014;
  glm::dvec2 fitting_cross_m{0.0};

  bool active() const { return full_add_curvature_per_m != 0.0; }
  // The added curvature at the distance s_m below the fitting cross (a(s) above).
  double add_curvature_per_m(double below_cross_m) const;
  SagSample sample(glm::dvec2 at_m) const;  // always valid
};

}  // namespace glarelab

#include "glare/refraction/spectacle_power.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/mat2x2.hpp>
#include <glm/matrix.hpp>

namespace glarelab {
namespace {

constexpr double kPencilOffset_m = 2e-5;  // h above
constexpr double kPencilStartAhead_m = 5e-3;
constexpr double kGazeStep_rad = 1e-5;  // neighbouring lines of sight for the angular magnification

// Rodrigues' rotation of v about the unit axis k by the angle with the given cosine and sine.
glm::dvec3 rotate(glm::dvec3 v, glm::dvec3 k, double cos_angle, double sin_angle) {
  return v * cos_angle + glm::cross(k, v) * sin_angle + k * glm::dot(k, v) * (1.0 - cos_angle);
}

}  // namespace

ListingFrame listing_eye_frame(glm::dvec3 gaze) {
  ListingFrame frame;
  const glm::dvec3 g = glm::normalize(gaze);
  const glm::dvec3 axis = glm::cross(glm::dvec3(0.0, 0.0, 1.0), g);
  const double sin_angle = glm::length(axis);
  frame.gaze = g;
  if (sin_angle < 1e-15) return frame;
  const glm::dvec3 k = axis / sin_angle;
  frame.right = rotate(glm::dvec3(1.0, 0.0, 0.0), k, g.z, sin_angle);
  frame.up = rotate(glm::dvec3(0.0, 1.0, 0.0), k, g.z, sin_angle);
  return frame;
}

GazePower lens_power_at_gaze(const SpectacleLens& lens, glm::dvec3 gaze, double wavelength_nm) {
  GazePower out;
  const LensRay chief = lens.trace_from_eye(gaze, wavelength_nm);
  out.outcome = chief.outcome;
  if (!chief.through()) return out;
  out.scene_direction = chief.direction;

  const ListingFrame eye = listing_eye_frame(gaze);
  const ListingFrame scene = listing_eye_frame(chief.direction);  // across the incoming pencil
  const glm::dvec3 toward_eye = -eye.gaze;                   // the chief ray's direction after the lens
  const glm::dvec3 vertex_point = eye.gaze * lens.vertex_sphere_radius_m();

  // Positions and slopes across the chief ray, at the vertex sphere, of the ray offset by `offset`.
  glm::dvec2 position[4], slope[4];
  const glm::dvec2 offsets[4] = {{kPencilOffset_m, 0.0}, {-kPencilOffset_m, 0.0}, {0.0, kPencilOffset_m}, {0.0, -kPencilOffset_m}};
  for (int i = 0; i < 4; ++i) {
    const glm::dvec3 start =
        chief.origin_m + kPencilStartAhead_m * chief.direction + offsets[i].x * scene.right + offsets[i].y * scene.up;
    const LensRay ray = lens.trace_from_scene(start, -chief.direction, wavelength_nm);
    if (!ray.through()) {
      out.outcome = ray.outcome;
      return out;
    }
    const double along = glm::dot(ray.direction, toward_eye);
    const double travel = glm::dot(vertex_point - ray.origin_m, toward_eye) / along;
    const glm::dvec3 at = ray.origin_m + travel * ray.direction - vertex_point;
    position[i] = glm::dvec2(glm::dot(at, eye.right), glm::dot(at, eye.up));
    slope[i] = glm::dvec2(glm::dot(ray.direction, eye.right), glm::dot(ray.direction, eye.up)) / along;
  }
  // Columns: derivatives along the two offsets (glm matrices are column-major).
  const double two_h = 2.0 * kPencilOffset_m;
  const glm::dmat2 d_position((position[0] - position[1]) / two_h, (position[2] - position[3]) / two_h);
  const glm::dmat2 d_slope((slope[0] - slope[1]) / two_h, (slope[2] - slope[3]) / two_h);
  glm::dmat2 vergence = -d_slope * glm::inverse(d_position);
  // A pencil from a point is a normal congruence, so V is symmetric; average away the rounding.
  const double xy = 0.5 * (vergence[0][1] + vergence[1][0]);
  vergence[0][1] = vergence[1][0] = xy;
  out.vertex_sphere = DioptricPower{vergence};
  out.at_cornea = effective_power_at_distance(out.vertex_sphere, lens.spec().vertex_distance_mm * 1e-3);

  // Neighbouring lines of sight +-kGazeStep_rad along the eye's x' and y', their scene directions as
  // angles (tangents) across the chief ray's.
  glm::dvec2 scene_angle[4];
  for (int i = 0; i < 4; ++i) {
    const glm::dvec2 turn = offsets[i] / kPencilOffset_m * kGazeStep_rad;
    const LensRay ray = lens.trace_from_eye(eye.gaze + turn.x * eye.right + turn.y * eye.up, wavelength_nm);
    if (!ray.through()) {
      out.outcome = ray.outcome;
      return out;
    }
    const double along = glm::dot(ray.direction, scene.gaze);
    scene_angle[i] = glm::dvec2(glm::dot(ray.direction, scene.right), glm::dot(ray.direction, scene.up)) / along;
  }
  out.scene_per_visual_angle = glm::dmat2((scene_angle[0] - scene_angle[1]) / (2.0 * kGazeStep_rad),
                                          (scene_angle[2] - scene_angle[3]) / (2.0 * kGazeStep_rad));
  out.through = true;
  return out;
}

}  // namespace glarelab

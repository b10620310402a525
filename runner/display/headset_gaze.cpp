#include "runner/display/headset_gaze.h"

#include <cmath>

namespace glarelab {
namespace {

constexpr double kRadiansPerDegree = 0.017453292519943295769;

// v rotated by the unit quaternion q (x, y, z, w): v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z).
std::array<double, 3> rotated(const double q[4], const std::array<double, 3>& v) {
  const double u[3] = {q[0], q[1], q[2]};
  const double w = q[3];
  const double c1[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  const double c2[3] = {u[1] * c1[2] - u[2] * c1[1], u[2] * c1[0] - u[0] * c1[2], u[0] * c1[1] - u[1] * c1[0]};
  return {v[0] + 2.0 * (w * c1[0] + c2[0]), v[1] + 2.0 * (w * c1[1] + c2[1]), v[2] + 2.0 * (w * c1[2] + c2[2])};
}

}  // namespace

std::array<double, 3> gaze_direction_in_view(const double gaze_orientation_xyzw[4], const double view_orientation_xyzw[4]) {
  const std::array<double, 3> in_space = rotated(gaze_orientation_xyzw, {0.0, 0.0, -1.0});
  const double inverse_view[4] = {-view_orientation_xyzw[0], -view_orientation_xyzw[1], -view_orientation_xyzw[2],
                                  view_orientation_xyzw[3]};
  return rotated(inverse_view, in_space);
}

std::optional<ViewGazePoint> gaze_point_in_view(const std::array<double, 3>& direction, const ViewFieldOfView& view) {
  if (!(direction[2] < 0.0)) return std::nullopt;
  const double tan_x = direction[0] / -direction[2];
  const double tan_y = direction[1] / -direction[2];
  const double tan_left = std::tan(view.left_deg * kRadiansPerDegree);
  const double tan_right = std::tan(view.right_deg * kRadiansPerDegree);
  const double tan_up = std::tan(view.up_deg * kRadiansPerDegree);
  const double tan_down = std::tan(view.down_deg * kRadiansPerDegree);
  return ViewGazePoint{(tan_x - tan_left) / (tan_right - tan_left), (tan_up - tan_y) / (tan_up - tan_down)};
}

}  // namespace glarelab

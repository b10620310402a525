#pragma once
// The geometry of a flat display seen from the eye, for tests that check glare at an angle from a
// lamp: each pixel's direction (line of sight through the display's centre), the angle between two
// pixels' directions and the solid angle of one pixel. Written out here, independently of the
// library's DisplayGeometry, so the tests check the library against it.
#include <cmath>
#include <numbers>

namespace glarelab::test {

struct Direction {
  double x, y, z;
};

struct DisplayDirections {
  int width_px = 0;
  int height_px = 0;
  double pitch_mm = 0.0;
  double distance_mm = 0.0;

  // The 3D direction (mm) from the eye to the centre of pixel (x, y).
  Direction direction_of(double x_px, double y_px) const {
    return {(x_px + 0.5 - 0.5 * width_px) * pitch_mm, (y_px + 0.5 - 0.5 * height_px) * pitch_mm, distance_mm};
  }
  // atan2(|a x b|, a . b): accurate at small angles too.
  static double angle_between_deg(const Direction& a, const Direction& b) {
    const double dot = a.x * b.x + a.y * b.y + a.z * b.z;
    const double cross = std::sqrt(std::pow(a.y * b.z - a.z * b.y, 2) + std::pow(a.z * b.x - a.x * b.z, 2) +
                                   std::pow(a.x * b.y - a.y * b.x, 2));
    return std::atan2(cross, dot) * 180.0 / std::numbers::pi;
  }
  double angle_between_pixels_deg(double ax_px, double ay_px, double bx_px, double by_px) const {
    return angle_between_deg(direction_of(ax_px, ay_px), direction_of(bx_px, by_px));
  }
  // d p^2 / r^3 (sr): the pixel's area foreshortened by cos = d / r, over r^2.
  double pixel_solid_angle_sr(double x_px, double y_px) const {
    const Direction d = direction_of(x_px, y_px);
    return distance_mm * pitch_mm * pitch_mm / std::pow(d.x * d.x + d.y * d.y + d.z * d.z, 1.5);
  }
};

}  // namespace glarelab::test

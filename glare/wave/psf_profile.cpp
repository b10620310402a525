#include "glare/wave/psf_profile.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/atomic_file.h"

namespace glarelab {
namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;
constexpr double kRec709LuminanceWeights[3] = {0.2126, 0.7152, 0.0722};

// The radius in pixels of an angle, and the solid angle of a pixel at a radius, for a layout.
double radius_px(PixelLayout layout, double angle_deg, double degrees_per_pixel) {
  if (layout == PixelLayout::uniform_angle) return angle_deg / degrees_per_pixel;
  return std::tan(angle_deg * kRadPerDeg) / std::tan(degrees_per_pixel * kRadPerDeg);
}

double pixel_solid_angle_sr(PixelLayout layout, double r_px, double degrees_per_pixel) {
  if (layout == PixelLayout::uniform_angle) return std::pow(degrees_per_pixel * kRadPerDeg, 2);
  const double t = std::tan(degrees_per_pixel * kRadPerDeg);
  return t * t / std::pow(1.0 + r_px * r_px * t * t, 1.5);
}

}  // namespace

std::vector<double> profile_angles_deg() {
  const double decades = std::log10(kProfileLastAngleDeg / kProfileFirstAngleDeg);
  const int steps = static_cast<int>(std::ceil(decades * kProfileAnglesPerDecade));
  std::vector<double> angles;
  for (int i = 0; i <= steps; ++i)
    angles.push_back(kProfileFirstAngleDeg * std::pow(10.0, decades * i / steps));
  angles.front() = kProfileFirstAngleDeg;  // exact ends, whatever pow rounds to
  angles.back() = kProfileLastAngleDeg;
  return angles;
}

std::vector<ProfilePoint> image_profile_per_sr(const Psf& psf, PixelLayout layout, const std::vector<double>& angles_deg,
                                               double reach_deg) {
  const int n = psf.size_px, centre = n / 2;
  const int rings = centre;  // ring k: pixels whose distance from the centre rounds to k, k < n / 2
  std::vector<double> sum(static_cast<std::size_t>(rings), 0.0), count(static_cast<std::size_t>(rings), 0.0);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double r = std::hypot(x - centre, y - centre);
      const auto k = static_cast<std::size_t>(std::lround(r));
      if (k >= sum.size()) continue;
      double value = 0.0;
      if (psf.channels == 1) value = psf.at(0, x, y);
      else
        for (int c = 0; c < 3; ++c) value += kRec709LuminanceWeights[c] * psf.at(c, x, y);
      sum[k] += value / pixel_solid_angle_sr(layout, r, psf.degrees_per_pixel);
      count[k] += 1.0;
    }
  for (std::size_t k = 0; k < sum.size(); ++k) sum[k] /= count[k];
  std::vector<ProfilePoint> points;
  for (double angle : angles_deg) {
    const double r = radius_px(layout, angle, psf.degrees_per_pixel);
    if (angle > reach_deg || !(r <= rings - 1)) continue;
    const auto k = static_cast<std::size_t>(std::min(std::floor(r), rings - 2.0));
    const double f = r - static_cast<double>(k);
    points.push_back({angle, (1.0 - f) * sum[k] + f * sum[k + 1]});
  }
  return points;
}

void write_profile_csv(const std::string& path, const std::vector<ProfilePoint>& points) {
  // Beside and renamed into place (core/atomic_file.h): never a half-written profile.
  AtomicFile file(path);
  std::ostream& out = file.stream();
  out.precision(17);
  out << "angle_deg,psf_per_sr\n";
  for (const ProfilePoint& point : points) out << point.angle_deg << "," << point.per_sr << "\n";
  file.commit();
}

}  // namespace glarelab

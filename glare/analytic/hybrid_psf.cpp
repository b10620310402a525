#include "glare/analytic/hybrid_psf.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <vector>

namespace glarelab {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// The display pixel's distance from the source pixel.
double radius_px(int dx, int dy) { return std::hypot(static_cast<double>(dx), static_cast<double>(dy)); }

}  // namespace

HandoverPixels handover_pixels(const HybridHandover& handover, const DisplayGeometry& geometry) {
  const double d = geometry.viewing_distance_mm, pitch = geometry.pixel_pitch_mm;
  return {d * std::tan(handover.inner_deg / kDegPerRad) / pitch, d * std::tan(handover.outer_deg / kDegPerRad) / pitch};
}

double handover_weight(double r_px, const HandoverPixels& handover) {
  if (r_px <= handover.inner_px) return 1.0;
  if (r_px >= handover.outer_px) return 0.0;
  // 1 - smoothstep: value and slope continuous at both radii.
  const double t = (r_px - handover.inner_px) / (handover.outer_px - handover.inner_px);
  return 1.0 - t * t * (3.0 - 2.0 * t);
}

DisplayKernel hybrid_far_kernel(const DisplayKernel& analytic, const HandoverPixels& handover) {
  // Only offsets inside the outer radius change (beyond it 1 - w is exactly 1): a whole frame's
  // kernel is millions of pixels, the annulus a few thousand.
  DisplayKernel far = analytic;
  const int reach_x = std::min(static_cast<int>(std::ceil(handover.outer_px)), far.half_width_px);
  const int reach_y = std::min(static_cast<int>(std::ceil(handover.outer_px)), far.half_height_px);
  for (int c = 0; c < far.channels; ++c)
    for (int dy = -reach_y; dy <= reach_y; ++dy)
      for (int dx = -reach_x; dx <= reach_x; ++dx)
        far.at(c, dx, dy) *= 1.0 - handover_weight(radius_px(dx, dy), handover);
  return far;
}

std::array<double, 3> analytic_energy_inside(const DisplayKernel& analytic, const HandoverPixels& handover) {
  std::array<double, 3> inside{0.0, 0.0, 0.0};
  const int reach_x = std::min(static_cast<int>(std::ceil(handover.outer_px)), analytic.half_width_px);
  const int reach_y = std::min(static_cast<int>(std::ceil(handover.outer_px)), analytic.half_height_px);
  for (int c = 0; c < analytic.channels; ++c)
    for (int dy = -reach_y; dy <= reach_y; ++dy)
      for (int dx = -reach_x; dx <= reach_x; ++dx)
        inside[static_cast<std::size_t>(c)] += handover_weight(radius_px(dx, dy), handover) * analytic.at(c, dx, dy);
  if (analytic.channels == 1) inside[1] = inside[2] = inside[0];
  return inside;
}

Psf hybrid_near_psf(const Psf& wave_display_psf, const std::array<double, 3>& analytic_inside,
                    const HandoverPixels& handover, std::array<double, 3>* scale_out) {
  const int n = wave_display_psf.size_px, centre = n / 2;
  // The weight must fall to 0 inside the grid: past its edge the wave PSF is unknown.
  if (handover.outer_px > centre - 1)
    throw HandoverError("the hand-over ends " + std::to_string(handover.outer_px) +
                        " display pixels from the source, beyond the wave-optics PSF's " + std::to_string(n) +
                        " px grid on the display");
  Psf near;
  near.size_px = n;
  near.degrees_per_pixel = wave_display_psf.degrees_per_pixel;
  near.channels = 3;
  near.values.assign(3 * static_cast<std::size_t>(n) * n, 0.0);
  for (int c = 0; c < 3; ++c) {
    const int from = wave_display_psf.channels == 1 ? 0 : c;
    double weighted_sum = 0.0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const double weighted = handover_weight(radius_px(x - centre, y - centre), handover) * wave_display_psf.at(from, x, y);
        near.at(c, x, y) = weighted;
        weighted_sum += weighted;
      }
    if (!(weighted_sum > 0.0))
      throw HandoverError("the wave-optics PSF holds no light inside the hand-over's outer radius (" +
                          std::to_string(handover.outer_px) + " display pixels)");
    const double scale = analytic_inside[static_cast<std::size_t>(c)] / weighted_sum;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) near.at(c, x, y) *= scale;
    if (scale_out) (*scale_out)[static_cast<std::size_t>(c)] = scale;
  }
  return near;
}

Psf calibrated_near_psf(const Psf& wave_display_psf, const DisplayKernel& analytic, const HandoverPixels& handover) {
  const int n = wave_display_psf.size_px, centre = n / 2;
  if (handover.outer_px > centre - 1)
    throw HandoverError("the hand-over ends " + std::to_string(handover.outer_px) +
                        " display pixels from the source, beyond the wave-optics PSF's " + std::to_string(n) +
                        " px grid on the display");
  // Rings 0..rings-1 hold every pixel where w > 0 (distance below the outer radius).
  const int reach = static_cast<int>(std::ceil(handover.outer_px));
  if (analytic.half_width_px < reach || analytic.half_height_px < reach)
    throw HandoverError("the analytic kernel (half size " + std::to_string(analytic.half_width_px) + " x " +
                        std::to_string(analytic.half_height_px) + " px) does not reach the hand-over's outer radius (" +
                        std::to_string(handover.outer_px) + " display pixels)");
  const int rings = static_cast<int>(std::lround(static_cast<double>(reach))) + 1;
  const auto ring_of = [](int dx, int dy) { return static_cast<int>(std::lround(radius_px(dx, dy))); };
  Psf near;
  near.size_px = n;
  near.degrees_per_pixel = wave_display_psf.degrees_per_pixel;
  near.channels = 3;
  near.values.assign(3 * static_cast<std::size_t>(n) * n, 0.0);
  for (int c = 0; c < 3; ++c) {
    const int from_wave = wave_display_psf.channels == 1 ? 0 : c, from_kernel = analytic.channels == 1 ? 0 : c;
    std::vector<double> wave_ring(static_cast<std::size_t>(rings), 0.0), kernel_ring(static_cast<std::size_t>(rings), 0.0);
    for (int dy = -reach; dy <= reach; ++dy)
      for (int dx = -reach; dx <= reach; ++dx) {
        const double w = handover_weight(radius_px(dx, dy), handover);
        if (w <= 0.0) continue;
        const auto k = static_cast<std::size_t>(ring_of(dx, dy));
        wave_ring[k] += w * wave_display_psf.at(from_wave, centre + dx, centre + dy);
        kernel_ring[k] += w * analytic.at(from_kernel, dx, dy);
      }
    for (int dy = -reach; dy <= reach; ++dy)
      for (int dx = -reach; dx <= reach; ++dx) {
        const double w = handover_weight(radius_px(dx, dy), handover);
        if (w <= 0.0) continue;
        const auto k = static_cast<std::size_t>(ring_of(dx, dy));
        near.at(c, centre + dx, centre + dy) =
            wave_ring[k] > 0.0 ? w * wave_display_psf.at(from_wave, centre + dx, centre + dy) * (kernel_ring[k] / wave_ring[k])
                               : w * analytic.at(from_kernel, dx, dy);
      }
  }
  return near;
}

}  // namespace glarelab

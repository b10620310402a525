#include "glare/hybrid_psf.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace glarelab {

double wave_psf_reach_deg(int grid_px, double reference_degrees_per_pixel) {
  return (grid_px / 2 - 1) * reference_degrees_per_pixel * (380.0 / 575.0);
}

HybridHandover default_handover(double reach_deg) { return {0.45 * reach_deg, 0.9 * reach_deg}; }

void check_handover(const HybridHandover& handover, double reach_deg) {
  std::ostringstream out;
  out.precision(4);
  if (!(handover.inner_deg > 0.0) || !(handover.outer_deg > handover.inner_deg)) {
    out << "the hand-over annulus " << handover.inner_deg << "-" << handover.outer_deg
        << " degrees must have 0 < inner < outer";
    throw HandoverError(out.str());
  }
  if (handover.outer_deg > reach_deg) {
    out << "the hand-over at " << handover.outer_deg << " degrees lies beyond the " << reach_deg
        << " degrees the wave-optics PSF's grid reaches in every channel (a larger grid or a smaller aperture width reaches farther)";
    throw HandoverError(out.str());
  }
}

HandoverPixels handover_pixels(const HybridHandover& handover, const DisplayGeometry& geometry) {
  auto px = [&](double deg) { return geometry.viewing_distance_mm * std::tan(deg * std::numbers::pi / 180.0) / geometry.pixel_pitch_mm; };
  return {px(handover.inner_deg), px(handover.outer_deg)};
}

double handover_weight(double r_px, const HandoverPixels& handover) {
  const double t = std::clamp((r_px - handover.inner_px) / (handover.outer_px - handover.inner_px), 0.0, 1.0);
  return 1.0 - t * t * (3.0 - 2.0 * t);
}

DisplayKernel hybrid_far_kernel(const DisplayKernel& analytic, const HandoverPixels& handover) {
  DisplayKernel far = analytic;
  for (int c = 0; c < far.channels; ++c)
    for (int dy = -far.half_height_px; dy <= far.half_height_px; ++dy)
      for (int dx = -far.half_width_px; dx <= far.half_width_px; ++dx) {
        const double w = handover_weight(std::hypot(static_cast<double>(dx), static_cast<double>(dy)), handover);
        if (w > 0.0) far.at(c, dx, dy) *= 1.0 - w;
      }
  return far;
}

std::array<double, 3> analytic_energy_inside(const DisplayKernel& analytic, const HandoverPixels& handover) {
  std::array<double, 3> inside{0.0, 0.0, 0.0};
  const int reach = static_cast<int>(std::ceil(handover.outer_px));
  for (int c = 0; c < analytic.channels; ++c)
    for (int dy = -std::min(reach, analytic.half_height_px); dy <= std::min(reach, analytic.half_height_px); ++dy)
      for (int dx = -std::min(reach, analytic.half_width_px); dx <= std::min(reach, analytic.half_width_px); ++dx)
        inside[c] += handover_weight(std::hypot(static_cast<double>(dx), static_cast<double>(dy)), handover) *
                     analytic.at(c, dx, dy);
  if (analytic.channels == 1) inside[1] = inside[2] = inside[0];
  return inside;
}

Psf hybrid_near_psf(const Psf& wave, const std::array<double, 3>& analytic_inside, const HandoverPixels& handover,
                    std::array<double, 3>* scale_out) {
  Psf near = wave;
  near.channels = 3;
  const std::size_t plane = static_cast<std::size_t>(wave.size_px) * wave.size_px;
  near.values.assign(3 * plane, 0.0);
  const int centre = wave.size_px / 2;
  for (int c = 0; c < 3; ++c) {
    const int wc = wave.channels == 3 ? c : 0;
    double weighted = 0.0;
    for (int y = 0; y < wave.size_px; ++y)
      for (int x = 0; x < wave.size_px; ++x) {
        const double w = handover_weight(std::hypot(static_cast<double>(x - centre), static_cast<double>(y - centre)), handover);
        near.at(c, x, y) = w * wave.at(wc, x, y);
        weighted += near.at(c, x, y);
      }
    const double s = weighted > 0.0 ? analytic_inside[c] / weighted : 0.0;
    for (std::size_t i = 0; i < plane; ++i) near.values[c * plane + i] *= s;
    if (scale_out) (*scale_out)[c] = s;
  }
  return near;
}

}  // namespace glarelab

#include "glare/hybrid_psf.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace glarelab {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
// The chromatic blur's shortest wavelength and its reference (spectral_psf.h, Ritschel et al. 2009
// section 5): the 380 nm copy of the reference PSF is read at theta * 575 / 380, so it leaves the
// grid 575 / 380 times nearer the centre than the reference does.
constexpr double kShortestBlurWavelengthNm = 380.0;
constexpr double kBlurReferenceWavelengthNm = 575.0;

std::string angle_text(double degrees) {
  std::ostringstream out;
  out.precision(4);
  out << degrees << " deg";
  return out.str();
}

// The display pixel's distance from the source pixel.
double radius_px(int dx, int dy) { return std::hypot(static_cast<double>(dx), static_cast<double>(dy)); }

}  // namespace

double wave_psf_reach_deg(int grid_px, double reference_degrees_per_pixel) {
  return (0.5 * grid_px - 1.0) * reference_degrees_per_pixel * (kShortestBlurWavelengthNm / kBlurReferenceWavelengthNm);
}

HybridHandover default_handover(double reach_deg) {
  const double outer_deg = 0.9 * reach_deg;
  return {0.5 * outer_deg, outer_deg};
}

void check_handover(const HybridHandover& handover, double reach_deg) {
  const std::string annulus = "the hand-over from " + angle_text(handover.inner_deg) + " to " + angle_text(handover.outer_deg);
  if (!std::isfinite(handover.inner_deg) || !std::isfinite(handover.outer_deg) || handover.inner_deg <= 0.0)
    throw HandoverError(annulus + " must start at a finite angle above 0 deg");
  if (handover.inner_deg >= handover.outer_deg)
    throw HandoverError(annulus + " is empty: its inner angle must lie below its outer angle");
  if (handover.outer_deg > reach_deg)
    throw HandoverError(annulus + " ends beyond the wave-optics PSF's reach, " + angle_text(reach_deg) +
                        " (half its grid less one pixel, at the chromatic blur's 380 nm): a larger grid or a "
                        "narrower aperture grid reaches farther");
}

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

}  // namespace glarelab

#pragma once
// The compact bright sources of a frame: the lamps whose glare shows the ciliary corona's lines
// (glare/analytic/ciliary_corona.h). Spencer et al. 1995, section 2.2: the rays are "brighter and
// more pronounced as the angle subtended by the source decreases", and the fine lines of every part
// of an areal source superimpose until "sources much larger than 20 minutes of arc did not have
// significant flare lines". So only sources that are bright against the frame and small in angle
// get lines; the rest of the frame's glare stays the smooth CIE 146 veil.
//
// A source is an 8-connected group of pixels whose Rec.709 luminance reaches the threshold
//     T = max(over_median x the frame's median luminance, of_peak x its peak),   T > 0.
// Why 1000 x the median: around a source of luminance L_s and solid angle Omega_s the veil at the
// corona's inner edge (2 degrees) is L_s Omega_s GSF(2 deg), about 1.7e-5 L_s for a 10 arcmin disc
// (GSF(2 deg) = 2.5 per sr); its lines modulate that by about a half, which reaches 1 % of the
// background (a Weber fraction the eye just sees) at L_s of about 1000 times the background. The
// median stands for the background: a few lamps do not move it. Why 1e-3 x the peak: on a black
// display (median 0) the dim content beside a lamp stays out.
#include <array>
#include <vector>

#include "core/image.h"

namespace glarelab {

struct CompactSource {
  double x_px = 0.0, y_px = 0.0;   // the energy-weighted centroid (pixel centres at integer coordinates)
  std::array<double, 3> energy{};  // R, G, B energy over its pixels (glare/analytic/pixel_solid_angle.h units)
  // The mean squared distance of its energy from the centroid, each pixel a uniform unit square
  // (a pixel's own square adds 1/6 px^2): a uniform disc of diameter s has s^2 / 8.
  double second_moment_px2 = 0.0;
  int pixels = 0;
  // The diameter of the uniform disc with the same second moment: sqrt(8 second_moment_px2).
  double disc_diameter_px() const;
};

struct CompactSourceRule {
  double over_median = 1000.0;
  double of_peak = 1e-3;
  // Groups whose disc diameter exceeds this are not sources (an areal light: no lines).
  double largest_diameter_px = 0.0;
  int most = 8;  // the most energetic ones (each costs a pass over its corona's annulus)
};

// The sources of a frame, most energetic (Rec.709 luminance of the energy) first. `luminance` is the
// frame in cd/m2, `energy` the same frame as energy per pixel (PixelSolidAngle::to_energy).
std::vector<CompactSource> compact_sources(const ImageRGBA& luminance, const ImageRGBA& energy, const CompactSourceRule& rule);

}  // namespace glarelab

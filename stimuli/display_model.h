#pragma once
// The physical display: geometry (pixels to degrees of visual angle) and photometry (cd/m2 to
// display drive values through the display encoding).
#include <array>

#include "core/display_spec.h"

namespace glarelab {

class DisplayModel {
 public:
  explicit DisplayModel(const DisplaySpec& spec) : spec_(spec) {}
  const DisplaySpec& spec() const { return spec_; }

  // Visual angle subtended by one pixel at the centre of the screen, seen from viewing_distance_mm:
  // 2 atan(pitch / 2d), in degrees.
  double degrees_per_pixel_at_centre() const;
  // Visual angle (degrees) of a span of `pixels` centred on the line of sight.
  double degrees_for_centred_span(double pixels) const;
  // The inverse: pixels of a span centred on the line of sight that subtends `degrees`,
  // 2 d tan(degrees / 2) / pitch (not rounded).
  double pixels_for_centred_span(double degrees) const;

  // Display drive value in [0, 1] for an achromatic luminance (cd/m2): clipped to the peak (and,
  // with a calibration table, to its black), then encoded. No quantisation or dithering.
  double encode(double luminance_cd_m2) const;
  // Drive values of the three channels for a linear Rec.709 stimulus (cd/m2 per channel): what the
  // encode pass (stimuli/shaders/encode_display.frag) computes before quantisation.
  std::array<double, 3> encode_rgb(const std::array<double, 3>& rec709_cd_m2) const;
  double frame_period_s() const { return 1.0 / spec_.refresh_hz; }

 private:
  DisplaySpec spec_;
};

// sRGB transfer function, IEC 61966-2-1:1999 (linear in [0,1] to encoded in [0,1]).
double srgb_encode(double linear);

// SMPTE ST 2084:2014 (PQ) inverse EOTF: absolute luminance (cd/m2, clipped to [0, 10000]) to the
// full-range signal N in [0, 1], N = ((c1 + c2 Y^m1) / (1 + c3 Y^m1))^m2 with Y = L / 10000.
double pq_encode(double luminance_cd_m2);
// The EOTF itself: signal N in [0, 1] to cd/m2.
double pq_decode(double signal);
// Highest luminance PQ encodes (cd/m2): Y = 1.
inline constexpr double kPqPeakCdM2 = 10000.0;

// ITU-R BT.2087-0 (2015), Eq. 2 matrix: linear Rec.709 RGB to linear BT.2020 RGB (same white, D65).
std::array<double, 3> rec709_to_bt2020(const std::array<double, 3>& rec709);

}  // namespace glarelab

#pragma once
// The physical display: geometry (pixels to degrees of visual angle) and photometry (cd/m2 to
// display drive values through the display encoding).
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

  // Display drive value in [0, 1] for a luminance (cd/m2): clipped to the peak, then encoded.
  double encode(double luminance_cd_m2) const;
  double frame_period_s() const { return 1.0 / spec_.refresh_hz; }

 private:
  DisplaySpec spec_;
};

// sRGB transfer function, IEC 61966-2-1:1999 (linear in [0,1] to encoded in [0,1]).
double srgb_encode(double linear);

}  // namespace glarelab

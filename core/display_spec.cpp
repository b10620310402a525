#include "core/display_spec.h"

#include <cmath>
#include <numbers>

namespace glarelab {

double centred_span_deg(const DisplaySpec& display, double pixels) {
  const double half_extent_mm = 0.5 * pixels * display.pixel_pitch_mm;
  return 2.0 * std::atan(half_extent_mm / display.viewing_distance_mm) * (180.0 / std::numbers::pi);
}

double centred_span_px(const DisplaySpec& display, double degrees) {
  return 2.0 * display.viewing_distance_mm * std::tan(0.5 * degrees * (std::numbers::pi / 180.0)) /
         display.pixel_pitch_mm;
}

int stimulus_gap_px(const DisplaySpec& display) {
  return static_cast<int>(std::lround(centred_span_px(display, display.stimulus_gap_deg)));
}

}  // namespace glarelab

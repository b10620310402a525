#include "stimuli/display_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace glarelab {

double srgb_encode(double linear) {
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

double DisplayModel::degrees_for_centred_span(double pixels) const { return centred_span_deg(spec_, pixels); }

double DisplayModel::pixels_for_centred_span(double degrees) const {
  return centred_span_px(spec_, degrees);
}

double DisplayModel::degrees_per_pixel_at_centre() const { return degrees_for_centred_span(1.0); }

double DisplayModel::encode(double luminance_cd_m2) const {
  const double relative = std::clamp(luminance_cd_m2 / spec_.peak_luminance_cd_m2, 0.0, 1.0);
  return spec_.encoding == DisplayEncoding::srgb ? srgb_encode(relative) : std::pow(relative, 1.0 / spec_.gamma);
}

}  // namespace glarelab

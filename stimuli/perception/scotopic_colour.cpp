#include "stimuli/perception/scotopic_colour.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "stimuli/perception/frame_adaptation_luminance.h"

namespace glarelab {

void validate_scotopic_settings(const ScotopicSettings& settings) {
  if (!std::isfinite(settings.spencer_saturation_reduction) || settings.spencer_saturation_reduction < 0.0 ||
      settings.spencer_saturation_reduction > 1.0)
    throw std::invalid_argument("perception scotopic: spencer_saturation_reduction must be in [0, 1] (got " +
                                std::to_string(settings.spencer_saturation_reduction) + ")");
}

void luidolt_scotopic_pixel(const double rgb[3], double rod_sensitivity, double out[3]) {
  static constexpr double kTint[3] = {1.05, 0.97, 1.27};  // Eq. 5.18's purple tint
  const double tone_mapped_luminance = luidolt_luminance_cd_m2(rgb[0], rgb[1], rgb[2]);
  for (int c = 0; c < 3; ++c)
    out[c] = rgb[c] * (1.0 - rod_sensitivity) + kTint[c] * tone_mapped_luminance * rod_sensitivity;
}

void spencer_desaturate_pixel(const double rgb[3], double saturation_reduction, double out[3]) {
  const double value = std::max({rgb[0], rgb[1], rgb[2]});
  // HSV keeps hue and value when every channel moves towards V by the same fraction: S = (V - min) / V
  // scales by (1 - reduction) and the ratios (V - c) / (V - min), which fix the hue, are unchanged.
  for (int c = 0; c < 3; ++c) out[c] = value - (value - rgb[c]) * (1.0 - saturation_reduction);
}

ImageRGBA apply_scotopic_colour(const ImageRGBA& tone_mapped, double rod_sensitivity,
                                const ScotopicSettings& settings) {
  validate_scotopic_settings(settings);
  if (!std::isfinite(rod_sensitivity) || rod_sensitivity < 0.0 || rod_sensitivity > 1.0)
    throw std::invalid_argument("perception scotopic: the rod sensitivity must be in [0, 1] (got " +
                                std::to_string(rod_sensitivity) + ")");
  ImageRGBA out = tone_mapped;
  for (int y = 0; y < out.height_px; ++y)
    for (int x = 0; x < out.width_px; ++x) {
      float* p = out.pixel(x, y);
      const double rgb[3] = {p[0], p[1], p[2]};
      double shifted[3];
      if (settings.form == ScotopicForm::luidolt_tint)
        luidolt_scotopic_pixel(rgb, rod_sensitivity, shifted);
      else
        spencer_desaturate_pixel(rgb, settings.spencer_saturation_reduction * rod_sensitivity, shifted);
      for (int c = 0; c < 3; ++c) p[c] = static_cast<float>(shifted[c]);
    }
  return out;
}

}  // namespace glarelab

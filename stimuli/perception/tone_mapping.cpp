#include "stimuli/perception/tone_mapping.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace glarelab {

void validate_tone_mapping_settings(const ToneMappingSettings& settings) {
  if (!std::isfinite(settings.middle_grey) || settings.middle_grey <= 0.0 || settings.middle_grey > 1.0)
    throw std::invalid_argument("perception tone mapping: middle_grey must be in (0, 1] (got " +
                                std::to_string(settings.middle_grey) + ")");
  if (!std::isfinite(settings.aces_pre_exposure) || settings.aces_pre_exposure <= 0.0 || settings.aces_pre_exposure > 10.0)
    throw std::invalid_argument("perception tone mapping: aces_pre_exposure must be in (0, 10] (got " +
                                std::to_string(settings.aces_pre_exposure) + ")");
  if (!std::isfinite(settings.minimum_adapted_luminance_cd_m2) || settings.minimum_adapted_luminance_cd_m2 <= 0.0)
    throw std::invalid_argument("perception tone mapping: minimum_adapted_luminance_cd_m2 must be finite and > 0 (got " +
                                std::to_string(settings.minimum_adapted_luminance_cd_m2) + ")");
}

double aces_narkowicz_curve(double x) {
  constexpr double a = 2.51, b = 0.03, c = 2.43, d = 0.59, e = 0.14;  // Narkowicz 2016
  return std::clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0, 1.0);
}

double tone_mapping_exposure_per_cd_m2(double adapted_luminance_cd_m2, const ToneMappingSettings& settings) {
  return settings.aces_pre_exposure * settings.middle_grey /
         std::max(adapted_luminance_cd_m2, settings.minimum_adapted_luminance_cd_m2);
}

double tone_map_channel_cd_m2(double channel_cd_m2, double adapted_luminance_cd_m2,
                              const ToneMappingSettings& settings, double peak_luminance_cd_m2) {
  if (settings.curve == ToneCurve::none) return std::clamp(channel_cd_m2, 0.0, peak_luminance_cd_m2);
  // Negative channels (out-of-gamut colours) would meet the curve's pole near x = -0.2; they are
  // black on a display anyway.
  const double x = std::max(channel_cd_m2, 0.0) * tone_mapping_exposure_per_cd_m2(adapted_luminance_cd_m2, settings);
  return peak_luminance_cd_m2 * aces_narkowicz_curve(x);
}

ImageRGBA tone_map(const ImageRGBA& frame, double adapted_luminance_cd_m2, const ToneMappingSettings& settings,
                   double peak_luminance_cd_m2) {
  validate_tone_mapping_settings(settings);
  if (!std::isfinite(peak_luminance_cd_m2) || peak_luminance_cd_m2 <= 0.0)
    throw std::invalid_argument("perception tone mapping: the display's peak_luminance_cd_m2 must be finite and > 0 (got " +
                                std::to_string(peak_luminance_cd_m2) + ")");
  if (!std::isfinite(adapted_luminance_cd_m2) || adapted_luminance_cd_m2 < 0.0)
    throw std::invalid_argument("perception tone mapping: the adapted luminance must be finite and >= 0 (got " +
                                std::to_string(adapted_luminance_cd_m2) + " cd/m2)");
  ImageRGBA out = frame;
  for (int y = 0; y < frame.height_px; ++y)
    for (int x = 0; x < frame.width_px; ++x) {
      float* p = out.pixel(x, y);
      for (int c = 0; c < 3; ++c)
        p[c] = static_cast<float>(tone_map_channel_cd_m2(p[c], adapted_luminance_cd_m2, settings, peak_luminance_cd_m2));
    }
  return out;
}

}  // namespace glarelab

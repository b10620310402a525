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

void validate_tone_mapping_inputs(const ToneMappingSettings& settings, double adapted_luminance_cd_m2,
                                  double peak_luminance_cd_m2) {
  validate_tone_mapping_settings(settings);
  if (!std::isfinite(peak_luminance_cd_m2) || peak_luminance_cd_m2 <= 0.0)
    throw std::invalid_argument("perception tone mapping: the display's peak_luminance_cd_m2 must be finite and > 0 (got " +
                                std::to_string(peak_luminance_cd_m2) + ")");
  if (!std::isfinite(adapted_luminance_cd_m2) || adapted_luminance_cd_m2 < 0.0)
    throw std::invalid_argument("perception tone mapping: the adapted luminance must be finite and >= 0 (got " +
                                std::to_string(adapted_luminance_cd_m2) + " cd/m2)");
}

double aces_narkowicz_curve(double x) {
  constexpr double a = 2.51, b = 0.03, c = 2.43, d = 0.59, e = 0.14;  // Narkowicz 2016
  return std::clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0, 1.0);
}

double aces_hill_rrt_odt_fit(double v) {
  // Hill (BakingLab ACES.hlsl): RRTAndODTFit.
  const double a = v * (v + 0.0245786) - 0.000090537;
  const double b = v * (0.983729 * v + 0.4329510) + 0.238081;
  return a / b;
}

void aces_hill_transform(const double rgb[3], double rgb_out[3]) {
  // sRGB => XYZ => D65_2_D60 => AP1 => RRT_SAT, and ODT_SAT => XYZ => D60_2_D65 => sRGB (Hill).
  static constexpr double kInput[3][3] = {
      {0.59719, 0.35458, 0.04823}, {0.07600, 0.90834, 0.01566}, {0.02840, 0.13383, 0.83777}};
  static constexpr double kOutput[3][3] = {
      {1.60475, -0.53108, -0.07367}, {-0.10208, 1.10813, -0.00605}, {-0.00327, -0.07276, 1.07602}};
  double fitted[3];
  for (int r = 0; r < 3; ++r)
    fitted[r] = aces_hill_rrt_odt_fit(kInput[r][0] * rgb[0] + kInput[r][1] * rgb[1] + kInput[r][2] * rgb[2]);
  for (int r = 0; r < 3; ++r)
    rgb_out[r] = std::clamp(kOutput[r][0] * fitted[0] + kOutput[r][1] * fitted[1] + kOutput[r][2] * fitted[2], 0.0, 1.0);
}

double tone_mapping_exposure_per_cd_m2(double adapted_luminance_cd_m2, const ToneMappingSettings& settings) {
  const double pre_exposure = settings.curve == ToneCurve::aces_narkowicz ? settings.aces_pre_exposure : 1.0;
  return pre_exposure * settings.middle_grey / std::max(adapted_luminance_cd_m2, settings.minimum_adapted_luminance_cd_m2);
}

void tone_map_pixel_cd_m2(const double rgb_cd_m2[3], double adapted_luminance_cd_m2, const ToneMappingSettings& settings,
                          double peak_luminance_cd_m2, double out_cd_m2[3]) {
  if (settings.curve == ToneCurve::none) {
    for (int c = 0; c < 3; ++c) out_cd_m2[c] = std::clamp(rgb_cd_m2[c], 0.0, peak_luminance_cd_m2);
    return;
  }
  // Negative channels (out-of-gamut colours) would meet the curves' poles (Narkowicz's near
  // x = -0.2); they are black on a display anyway.
  const double exposure = tone_mapping_exposure_per_cd_m2(adapted_luminance_cd_m2, settings);
  double x[3];
  for (int c = 0; c < 3; ++c) x[c] = std::max(rgb_cd_m2[c], 0.0) * exposure;
  if (settings.curve == ToneCurve::aces_hill) {
    double relative[3];
    aces_hill_transform(x, relative);
    for (int c = 0; c < 3; ++c) out_cd_m2[c] = peak_luminance_cd_m2 * relative[c];
    return;
  }
  for (int c = 0; c < 3; ++c) out_cd_m2[c] = peak_luminance_cd_m2 * aces_narkowicz_curve(x[c]);
}

double tone_map_channel_cd_m2(double channel_cd_m2, double adapted_luminance_cd_m2,
                              const ToneMappingSettings& settings, double peak_luminance_cd_m2) {
  const double grey[3] = {channel_cd_m2, channel_cd_m2, channel_cd_m2};
  double out[3];
  tone_map_pixel_cd_m2(grey, adapted_luminance_cd_m2, settings, peak_luminance_cd_m2, out);
  return out[1];
}

ImageRGBA tone_map(const ImageRGBA& frame, double adapted_luminance_cd_m2, const ToneMappingSettings& settings,
                   double peak_luminance_cd_m2) {
  validate_tone_mapping_inputs(settings, adapted_luminance_cd_m2, peak_luminance_cd_m2);
  ImageRGBA out = frame;
  for (int y = 0; y < frame.height_px; ++y)
    for (int x = 0; x < frame.width_px; ++x) {
      float* p = out.pixel(x, y);
      const double in[3] = {p[0], p[1], p[2]};
      double mapped[3];
      tone_map_pixel_cd_m2(in, adapted_luminance_cd_m2, settings, peak_luminance_cd_m2, mapped);
      for (int c = 0; c < 3; ++c) p[c] = static_cast<float>(mapped[c]);
    }
  return out;
}

}  // namespace glarelab

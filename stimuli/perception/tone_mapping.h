#pragma once
// Tone mapping with the adapted luminance (Luidolt 2020, sections 3.4 and 6.1, Fig. 6.1): the thesis
// uses "the Academy Color Encoding System Filmic tonemapper [DFD+15]" of Unreal Engine 4.20 and gives
// none of its constants. The published closed form of that curve is Narkowicz's fit of the ACES
// reference rendering and output transforms, ODT(RRT(x)) for Rec.709 with the 2.4 gamma removed
// (K. Narkowicz, "ACES Filmic Tone Mapping Curve", 2016-01-06, knarkowicz.wordpress.com; the fit the
// blog names as Unreal Engine 4's default curve since 4.8), applied to each channel:
//   f(x) = clamp(x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), 0, 1).
// The fit's input is "pre-exposed" (1 maps to ~0.8); Narkowicz: "for the original ACES curve just
// multiply input (x) by 0.6". Exposure (the key rule): the adapted luminance is the scene's middle
// grey, which ACES scene-linear values put at 0.18, so
//   x = 0.6 * 0.18 * c / L_a            (c a channel in cd/m2, L_a the adapted luminance in cd/m2)
// and the output is f(x) times the display's peak luminance, in display cd/m2. L_a is floored at
// 1e-6 cd/m2, the bottom of the visual range in the thesis' Fig. 2.8, so a black history is defined.
// `aces_hill` is Stephen Hill's fit of the same transforms with their colour handling (BakingLab,
// ACES.hlsl, 2016, MIT licence): linear sRGB -> ACES AP1 with the RRT's desaturation (ACESInputMat),
// the per-channel fit RRTAndODTFit(v) = (v (v + 0.0245786) - 0.000090537) /
// (v (0.983729 v + 0.4329510) + 0.238081), then back with the ODT's desaturation (ACESOutputMat),
// clamped to [0, 1]. It is fitted to the untouched ACES input, so its exposure has no 0.6: middle
// grey 0.18 goes in as 0.18 and comes out at 0.1056 (ACES puts 18 % grey near 10 % of the display).
// Both matrices' rows sum to 1 (to 1e-5), so a grey stays grey.
// `none` is the display's present behaviour: each channel clipped to [0, peak].
#include "core/image.h"
#include "core/perception_settings.h"

namespace glarelab {

// Throws std::invalid_argument naming the field and its accepted range.
void validate_tone_mapping_settings(const ToneMappingSettings& settings);
// The settings, and a frame's adapted luminance and the display's peak, checked as every tone
// mapping (CPU float64 and float32, GL) checks them before it maps a frame.
void validate_tone_mapping_inputs(const ToneMappingSettings& settings, double adapted_luminance_cd_m2,
                                  double peak_luminance_cd_m2);

// Narkowicz's fitted ACES curve, display-relative output in [0, 1].
double aces_narkowicz_curve(double x);
// Hill's RRTAndODTFit on one AP1 channel (unclamped), and the whole of Hill's transform on linear
// sRGB in [0, inf) to display-relative rgb_out in [0, 1].
double aces_hill_rrt_odt_fit(double v);
void aces_hill_transform(const double rgb[3], double rgb_out[3]);
// The factor from cd/m2 to the curve's input: middle_grey / max(L_a, floor), times pre_exposure
// for aces_narkowicz.
double tone_mapping_exposure_per_cd_m2(double adapted_luminance_cd_m2, const ToneMappingSettings& settings);
// One pixel, cd/m2 in, display cd/m2 out (0 .. peak).
void tone_map_pixel_cd_m2(const double rgb_cd_m2[3], double adapted_luminance_cd_m2, const ToneMappingSettings& settings,
                          double peak_luminance_cd_m2, double out_cd_m2[3]);
// One channel of a grey pixel (all three channels equal), for curves and tests.
double tone_map_channel_cd_m2(double channel_cd_m2, double adapted_luminance_cd_m2,
                              const ToneMappingSettings& settings, double peak_luminance_cd_m2);
// The frame (alpha kept).
ImageRGBA tone_map(const ImageRGBA& frame, double adapted_luminance_cd_m2, const ToneMappingSettings& settings,
                   double peak_luminance_cd_m2);

}  // namespace glarelab

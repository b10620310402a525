#include "stimuli/perception/perception_stages_float.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/parallel_for.h"
#include "glare/eye/pupil_model.h"
#include "stimuli/perception/acuity_loss_float.h"

namespace glarelab {
namespace {

// body(pixel) on every pixel's RGBA, rows split over threads.
template <typename Body>
void for_each_pixel(ImageRGBA& frame, int threads, Body body) {
  parallel_chunks(frame.height_px, threads, [&](int first, int last) {
    float* p = frame.pixel(0, first);
    float* const end = frame.pixel(0, 0) + 4 * static_cast<std::size_t>(last) * frame.width_px;
    for (; p != end; p += 4) body(p);
  });
}

// curve(value) on every colour value of the frame (alpha kept), rows split over threads, in blocks
// of four pixels: a loop of fixed count over all 16 values, which the compiler vectorises at -O2,
// the alphas put back after it.
template <typename Curve>
void for_each_colour_value(ImageRGBA& frame, int threads, Curve curve) {
  parallel_chunks(frame.height_px, threads, [&](int first, int last) {
    // A copy of its own: the frame's stores cannot then alias the curve's constants, which stay in
    // registers (the reference `curve` would have to be reloaded after each store).
    const Curve own = curve;
    float* p = frame.pixel(0, first);
    float* const end = frame.pixel(0, 0) + 4 * static_cast<std::size_t>(last) * frame.width_px;
    for (; p + 16 <= end; p += 16) {
      const float alpha[4] = {p[3], p[7], p[11], p[15]};
      for (int k = 0; k < 16; ++k) p[k] = own(p[k]);
      for (int k = 0; k < 4; ++k) p[4 * k + 3] = alpha[k];
    }
    for (; p != end; p += 4)
      for (int c = 0; c < 3; ++c) p[c] = own(p[c]);
  });
}

// Narkowicz's fit (aces_narkowicz_curve) in float on max(value, 0) times the exposure, the input
// held at 16 (the clamped curve is 1 from x = 7.24 on): one division per value, as the fit's own.
// The selects are written as maxps and minps do them (the second operand where the comparison
// fails), so the scalar form and the vector form below give the same bits.
float narkowicz(float value, float exposure) {
  float x = (value > 0.0f ? value : 0.0f) * exposure;
  x = x < 16.0f ? x : 16.0f;
  const float y = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
  return y < 1.0f ? y : 1.0f;  // y >= 0: x >= 0 and the denominator > 0
}

// peak * narkowicz on every colour value of rows [first, last), alpha kept. GCC 12 at -O2 does not
// vectorise the scalar form's loop (with the trapping-math default it cannot if-convert a select
// whose arm it has folded to a constant), and a scalar division per value kept the stage at four
// times its floor; so on SSE2 four values go at once: the pixel's R, G, B and A, the alpha put back
// by a mask.
void narkowicz_rows(ImageRGBA& frame, int first, int last, float exposure, float peak) {
  float* p = frame.pixel(0, first);
  float* const end = frame.pixel(0, 0) + 4 * static_cast<std::size_t>(last) * frame.width_px;
#if defined(__SSE2__)
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f), held = _mm_set1_ps(16.0f);
  const __m128 scale = _mm_set1_ps(exposure), peak4 = _mm_set1_ps(peak);
  const __m128 a1 = _mm_set1_ps(2.51f), b1 = _mm_set1_ps(0.03f), a2 = _mm_set1_ps(2.43f), b2 = _mm_set1_ps(0.59f),
               c2 = _mm_set1_ps(0.14f);
  const __m128 alpha_lane = _mm_castsi128_ps(_mm_set_epi32(-1, 0, 0, 0));
  for (; p != end; p += 4) {
    const __m128 in = _mm_loadu_ps(p);
    const __m128 x = _mm_min_ps(_mm_mul_ps(_mm_max_ps(in, zero), scale), held);
    const __m128 numerator = _mm_mul_ps(x, _mm_add_ps(_mm_mul_ps(a1, x), b1));
    const __m128 denominator = _mm_add_ps(_mm_mul_ps(x, _mm_add_ps(_mm_mul_ps(a2, x), b2)), c2);
    const __m128 mapped = _mm_mul_ps(peak4, _mm_min_ps(_mm_div_ps(numerator, denominator), one));
    _mm_storeu_ps(p, _mm_or_ps(_mm_and_ps(alpha_lane, in), _mm_andnot_ps(alpha_lane, mapped)));
  }
#endif
  for (; p != end; p += 4)
    for (int c = 0; c < 3; ++c) p[c] = peak * narkowicz(p[c], exposure);
}

// Hill's RRTAndODTFit (aces_hill_rrt_odt_fit) in float; its input held at 1e15, where the fit is
// 1 / 0.983729 to float precision, so the squares cannot overflow.
inline float hill_fit(float v) {
  v = std::min(v, 1e15f);
  return (v * (v + 0.0245786f) - 0.000090537f) / (v * (0.983729f * v + 0.4329510f) + 0.238081f);
}

}  // namespace

int perception_float_threads() { return static_cast<int>(resolved_threads(0)); }

void tone_map_float(ImageRGBA& frame, double adapted_luminance_cd_m2, const ToneMappingSettings& settings,
                    double peak_luminance_cd_m2, int threads) {
  validate_tone_mapping_inputs(settings, adapted_luminance_cd_m2, peak_luminance_cd_m2);
  const auto peak = static_cast<float>(peak_luminance_cd_m2);
  if (settings.curve == ToneCurve::none) {
    for_each_colour_value(frame, threads, [peak](float value) { return std::clamp(value, 0.0f, peak); });
    return;
  }
  const auto exposure = static_cast<float>(tone_mapping_exposure_per_cd_m2(adapted_luminance_cd_m2, settings));
  if (settings.curve == ToneCurve::aces_narkowicz) {
    parallel_chunks(frame.height_px, threads, [&](int first, int last) { narkowicz_rows(frame, first, last, exposure, peak); });
    return;
  }
  // aces_hill_transform's matrices (Hill, BakingLab ACES.hlsl).
  static constexpr float kInput[3][3] = {{0.59719f, 0.35458f, 0.04823f}, {0.07600f, 0.90834f, 0.01566f}, {0.02840f, 0.13383f, 0.83777f}};
  static constexpr float kOutput[3][3] = {
      {1.60475f, -0.53108f, -0.07367f}, {-0.10208f, 1.10813f, -0.00605f}, {-0.00327f, -0.07276f, 1.07602f}};
  for_each_pixel(frame, threads, [peak, exposure](float* p) {
    float x[3], fitted[3];
    for (int c = 0; c < 3; ++c) x[c] = std::max(p[c], 0.0f) * exposure;
    for (int r = 0; r < 3; ++r) fitted[r] = hill_fit(kInput[r][0] * x[0] + kInput[r][1] * x[1] + kInput[r][2] * x[2]);
    for (int r = 0; r < 3; ++r)
      p[r] = peak * std::clamp(kOutput[r][0] * fitted[0] + kOutput[r][1] * fitted[1] + kOutput[r][2] * fitted[2], 0.0f, 1.0f);
  });
}

void apply_scotopic_colour_float(ImageRGBA& frame, double rod_sensitivity, const ScotopicSettings& settings, int threads) {
  validate_scotopic_settings(settings);
  if (!std::isfinite(rod_sensitivity) || rod_sensitivity < 0.0 || rod_sensitivity > 1.0)
    throw std::invalid_argument("perception scotopic: the rod sensitivity must be in [0, 1] (got " +
                                std::to_string(rod_sensitivity) + ")");
  if (settings.form == ScotopicForm::luidolt_tint) {
    // Eq. 5.18 with the tint's weight and Eq. 5.1's folded into one 3 x 3 matrix per frame:
    // out_c = (1 - sigma) in_c + tint_c sigma (0.2125 r + 0.7154 g + 0.0721 b).
    static constexpr double kTint[3] = {1.05, 0.97, 1.27}, kLuminance[3] = {0.2125, 0.7154, 0.0721};
    float matrix[3][3];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        matrix[r][c] = static_cast<float>((r == c ? 1.0 - rod_sensitivity : 0.0) + kTint[r] * rod_sensitivity * kLuminance[c]);
    for_each_pixel(frame, threads, [&matrix](float* p) {
      const float in[3] = {p[0], p[1], p[2]};
      for (int r = 0; r < 3; ++r) p[r] = matrix[r][0] * in[0] + matrix[r][1] * in[1] + matrix[r][2] * in[2];
    });
    return;
  }
  const auto keep = static_cast<float>(1.0 - settings.spencer_saturation_reduction * rod_sensitivity);
  for_each_pixel(frame, threads, [keep](float* p) {
    const float value = std::max({p[0], p[1], p[2]});
    for (int c = 0; c < 3; ++c) p[c] = value - (value - p[c]) * keep;
  });
}

PerceptionResult run_perception_stages_float(const ImageRGBA& scene, const PerceptionFrameInput& input,
                                             TemporalAdaptation& eye, const PerceptionSettings& settings,
                                             const DisplaySpec& display, const PerceptionGlare& glare, int threads) {
  check_perception_inputs(eye, settings);
  PerceptionResult result;
  // Section 5.1: on the scene, before glare.
  result.frame_luminance_cd_m2 = frame_adaptation_luminance_float_cd_m2(scene, input.gaze_x, input.gaze_y,
                                                                        settings.adaptation_weighting, threads);
  if (settings.adaptation) {
    result.adapted_luminance_cd_m2 = eye.advance(result.frame_luminance_cd_m2, input.frame_time_s);
    result.stages_run.push_back(PerceptionStage::adaptation);
  } else {
    result.adapted_luminance_cd_m2 = result.frame_luminance_cd_m2;
  }
  // Two statements, not `c ? glare(scene) : scene`: that expression's type is const ImageRGBA, so the
  // glared frame would be copied into the result rather than moved (a whole frame a frame).
  if (settings.glare && glare) {
    result.image = glare(scene);
    result.stages_run.push_back(PerceptionStage::glare);
  } else {
    result.image = scene;
  }
  if (settings.acuity) {
    apply_acuity_loss_float(result.image, settings.acuity_settings, display_pixels_per_degree(display), threads);
    result.stages_run.push_back(PerceptionStage::acuity);
  }
  if (settings.tone_mapping) {
    tone_map_float(result.image, result.adapted_luminance_cd_m2, settings.tone_mapping_settings,
                   display.peak_luminance_cd_m2, threads);
    result.stages_run.push_back(PerceptionStage::tone_mapping);
  }
  if (settings.scotopic) {
    const double sigma =
        rod_sensitivity(result.adapted_luminance_cd_m2, settings.adaptation_time_constants.rod_half_sensitivity_cd_m2);
    apply_scotopic_colour_float(result.image, sigma, settings.scotopic_settings, threads);
    result.stages_run.push_back(PerceptionStage::scotopic);
  }
  return result;
}

}  // namespace glarelab

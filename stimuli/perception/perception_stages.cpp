#include "stimuli/perception/perception_stages.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "glare/eye/pupil_model.h"

namespace glarelab {
namespace {

// Re-throws a stage's own validation message with the settings group in front, so the message
// names the field as the experiment file's table would ("acuity: ... max_sigma_px ...").
template <typename Check>
void validate_group(const char* group, Check check) {
  try {
    check();
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(std::string("perception settings [") + group + "]: " + error.what());
  }
}

}  // namespace

const char* perception_stage_name(PerceptionStage stage) {
  switch (stage) {
    case PerceptionStage::adaptation: return "adaptation";
    case PerceptionStage::glare: return "glare";
    case PerceptionStage::acuity: return "acuity";
    case PerceptionStage::tone_mapping: return "tone_mapping";
    case PerceptionStage::scotopic: return "scotopic";
  }
  return "unknown";
}

void validate_perception_settings(const PerceptionSettings& settings) {
  validate_group("adaptation", [&] {
    const double sigma = settings.adaptation_weighting.gaze_sigma_frame_widths;
    if (!std::isfinite(sigma) || sigma <= 0.0 || sigma > 10.0)
      throw std::invalid_argument("gaze_sigma_frame_widths must be in (0, 10] (got " + std::to_string(sigma) + ")");
    const int size = settings.adaptation_weighting.resampled_size_px, top = settings.adaptation_weighting.top_level_size_px;
    if (size < 1 || size > 4096)
      throw std::invalid_argument("resampled_size_px must be in [1, 4096] (got " + std::to_string(size) + ")");
    if (top < 1 || top > size || size % top != 0 || ((size / top) & (size / top - 1)) != 0)
      throw std::invalid_argument("top_level_size_px must be in [1, resampled_size_px] with resampled_size_px / "
                                  "top_level_size_px a power of two (got " + std::to_string(top) + ")");
    validate_adaptation_time_constants(settings.adaptation_time_constants);
  });
  validate_group("acuity", [&] { validate_acuity_settings(settings.acuity_settings); });
  validate_group("tone_mapping", [&] { validate_tone_mapping_settings(settings.tone_mapping_settings); });
  validate_group("scotopic", [&] { validate_scotopic_settings(settings.scotopic_settings); });
}

void check_perception_inputs(const TemporalAdaptation& eye, const PerceptionSettings& settings) {
  validate_perception_settings(settings);
  const AdaptationTimeConstants& eye_constants = eye.constants();
  const AdaptationTimeConstants& wanted = settings.adaptation_time_constants;
  if (eye_constants.rod_time_constant_s != wanted.rod_time_constant_s ||
      eye_constants.cone_time_constant_s != wanted.cone_time_constant_s ||
      eye_constants.rod_half_sensitivity_cd_m2 != wanted.rod_half_sensitivity_cd_m2)
    throw std::invalid_argument("perception settings [adaptation]: the eye was made with other time constants than "
                                "adaptation_time_constants; make it from the same settings");
}

PerceptionResult run_perception_stages(const ImageRGBA& scene, const PerceptionFrameInput& input,
                                       TemporalAdaptation& eye, const PerceptionSettings& settings,
                                       const DisplaySpec& display, const PerceptionGlare& glare) {
  check_perception_inputs(eye, settings);
  PerceptionResult result;
  // Section 5.1: on the scene, before glare.
  result.frame_luminance_cd_m2 =
      frame_adaptation_luminance_cd_m2(scene, input.gaze_x, input.gaze_y, settings.adaptation_weighting);
  if (settings.adaptation) {
    result.adapted_luminance_cd_m2 = eye.advance(result.frame_luminance_cd_m2, input.frame_time_s);
    result.stages_run.push_back(PerceptionStage::adaptation);
  } else {
    result.adapted_luminance_cd_m2 = result.frame_luminance_cd_m2;
  }
  result.image = scene;
  if (settings.glare && glare) {
    result.image = glare(result.image);
    result.stages_run.push_back(PerceptionStage::glare);
  }
  if (settings.acuity) {
    result.image = apply_acuity_loss(result.image, settings.acuity_settings, display_pixels_per_degree(display));
    result.stages_run.push_back(PerceptionStage::acuity);
  }
  if (settings.tone_mapping) {
    result.image = tone_map(result.image, result.adapted_luminance_cd_m2, settings.tone_mapping_settings,
                            display.peak_luminance_cd_m2);
    result.stages_run.push_back(PerceptionStage::tone_mapping);
  }
  if (settings.scotopic) {
    const double sigma =
        rod_sensitivity(result.adapted_luminance_cd_m2, settings.adaptation_time_constants.rod_half_sensitivity_cd_m2);
    result.image = apply_scotopic_colour(result.image, sigma, settings.scotopic_settings);
    result.stages_run.push_back(PerceptionStage::scotopic);
  }
  return result;
}

}  // namespace glarelab

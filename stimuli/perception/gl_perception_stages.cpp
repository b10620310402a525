#include "stimuli/perception/gl_perception_stages.h"

#include <stdexcept>
#include <utility>
#include <vector>

#include "glare/eye/pupil_model.h"

namespace glarelab::gl {

PerceptionResult GlPerceptionStages::run(const ImageRGBA& scene, const PerceptionFrameInput& input,
                                         TemporalAdaptation& eye, const PerceptionSettings& settings,
                                         const DisplaySpec& display, const PerceptionGlare& glare) {
  check_perception_inputs(eye, settings);
  if (scene.empty()) throw std::invalid_argument("perception adaptation: the frame is empty");
  if (!frame_ || frame_->width_px() != scene.width_px || frame_->height_px() != scene.height_px) {
    frame_ = std::make_unique<GlFrameBuffer>(scene.width_px, scene.height_px);
    blurred_ = std::make_unique<GlFrameBuffer>(scene.width_px, scene.height_px);
  }
  frame_->upload(scene);

  PerceptionResult result;
  // Section 5.1: on the scene, before glare.
  result.frame_luminance_cd_m2 =
      adaptation_.luminance_cd_m2(*frame_, input.gaze_x, input.gaze_y, settings.adaptation_weighting);
  if (settings.adaptation) {
    result.adapted_luminance_cd_m2 = eye.advance(result.frame_luminance_cd_m2, input.frame_time_s);
    result.stages_run.push_back(PerceptionStage::adaptation);
  } else {
    result.adapted_luminance_cd_m2 = result.frame_luminance_cd_m2;
  }
  std::vector<float> depth = scene.depth;  // passes through the stages, as in the reference
  if (settings.glare && glare) {
    const ImageRGBA glared = glare(scene);
    frame_->upload(glared);
    depth = glared.depth;
    result.stages_run.push_back(PerceptionStage::glare);
  }
  GlFrameBuffer* current = frame_.get();
  if (settings.acuity) {
    acuity_.apply(*current, settings.acuity_settings, display_pixels_per_degree(display), *blurred_);
    current = blurred_.get();
    result.stages_run.push_back(PerceptionStage::acuity);
  }
  if (settings.tone_mapping) {
    tone_mapping_.apply(*current, result.adapted_luminance_cd_m2, settings.tone_mapping_settings,
                        display.peak_luminance_cd_m2, *current);
    result.stages_run.push_back(PerceptionStage::tone_mapping);
  }
  if (settings.scotopic) {
    const double sigma =
        rod_sensitivity(result.adapted_luminance_cd_m2, settings.adaptation_time_constants.rod_half_sensitivity_cd_m2);
    scotopic_.apply(*current, sigma, settings.scotopic_settings, *current);
    result.stages_run.push_back(PerceptionStage::scotopic);
  }
  result.image = current->download();
  result.image.depth = std::move(depth);
  return result;
}

}  // namespace glarelab::gl

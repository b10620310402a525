#include "stimuli/perception/gl_perception_stages.h"

#include <stdexcept>
#include <utility>
#include <vector>

#include "core/gl/shader_program.h"
#include "glare/eye/pupil_model.h"

namespace glarelab::gl {

PerceptionResult GlPerceptionStages::run(const ImageRGBA& scene, const PerceptionFrameInput& input,
                                         TemporalAdaptation& eye, const PerceptionSettings& settings,
                                         const DisplaySpec& display, const PerceptionGlare& glare) {
  std::vector<float> depth = scene.depth;  // passes through the stages, as in the reference
  GlareOnGpu uploaded;
  if (glare)
    uploaded = [&](const ImageRGBA& adapted, GlFrameBuffer& out) {
      const ImageRGBA glared = glare(adapted);
      out.upload(glared);
      depth = glared.depth;
    };
  PerceptionResult result;
  const GlFrameBuffer& last = run_stages(scene, input, eye, settings, display, uploaded, 0, result);
  result.image = last.download();
  stamp("read back");
  read_stamps(result);
  result.image.depth = std::move(depth);
  return result;
}

void GlPerceptionStages::stamp(const char* stage_done) {
  const std::size_t next = stage_done == nullptr ? 0 : stamped_.size() + 1;
  if (stage_done == nullptr) stamped_.clear();
  else stamped_.push_back(stage_done);
  while (timestamps_.size() <= next) timestamps_.push_back(create_query(GL_TIMESTAMP));
  glQueryCounter(timestamps_[next].get(), GL_TIMESTAMP);
}

void GlPerceptionStages::read_stamps(PerceptionResult& result) {
  // Waits for the GPU to reach the last query (the frame's end): the stages' times on its clock.
  std::vector<GLuint64> stamps_ns(stamped_.size() + 1, 0);
  for (std::size_t s = 0; s < stamps_ns.size(); ++s)
    glGetQueryObjectui64v(timestamps_[s].get(), GL_QUERY_RESULT, &stamps_ns[s]);
  result.gpu_stages_s.clear();
  for (std::size_t s = 0; s < stamped_.size(); ++s)
    result.gpu_stages_s.emplace_back(
        stamped_[s], stamps_ns[s + 1] > stamps_ns[s] ? 1e-9 * static_cast<double>(stamps_ns[s + 1] - stamps_ns[s]) : 0.0);
}

PerceptionResult GlPerceptionStages::run_on_gpu(const ImageRGBA& scene, const PerceptionFrameInput& input,
                                                TemporalAdaptation& eye, const PerceptionSettings& settings,
                                                const DisplaySpec& display, const GlareOnGpu& glare,
                                                std::uint64_t scene_token, std::shared_ptr<GlFrameBuffer>& out) {
  PerceptionResult result;
  const GlFrameBuffer& last = run_stages(scene, input, eye, settings, display, glare, scene_token, result);
  out = std::make_shared<GlFrameBuffer>(scene.width_px, scene.height_px);
  out->copy_from(last.buffer());
  stamp("kept");
  check_gl_error("perception GL: keeping the perceived frame");
  read_stamps(result);
  return result;
}

void GlPerceptionStages::load_scene(const ImageRGBA& scene, std::uint64_t scene_token) {
  const bool kept = scene_token != 0 && scene_token == kept_scene_token_ && kept_scene_ &&
                    kept_scene_->width_px() == scene.width_px && kept_scene_->height_px() == scene.height_px;
  if (kept) {
    // The frames of an interval: 33 MB at 1920 x 1080 copied on the GPU, where the upload from the
    // host took 7.7 ms of the H200's frame (docs/PERFORMANCE.md, 30 November).
    frame_->copy_from(kept_scene_->buffer());
    return;
  }
  ++scene_uploads_;
  if (scene_token == 0) {
    frame_->upload(scene);
    return;
  }
  if (!kept_scene_ || kept_scene_->width_px() != scene.width_px || kept_scene_->height_px() != scene.height_px)
    kept_scene_ = std::make_unique<GlFrameBuffer>(scene.width_px, scene.height_px);
  kept_scene_token_ = 0;  // until the upload below is made
  kept_scene_->upload(scene);
  kept_scene_token_ = scene_token;
  frame_->copy_from(kept_scene_->buffer());
}

GlFrameBuffer& GlPerceptionStages::run_stages(const ImageRGBA& scene, const PerceptionFrameInput& input,
                                              TemporalAdaptation& eye, const PerceptionSettings& settings,
                                              const DisplaySpec& display, const GlareOnGpu& glare,
                                              std::uint64_t scene_token, PerceptionResult& result) {
  check_perception_inputs(eye, settings);
  if (scene.empty()) throw std::invalid_argument("perception adaptation: the frame is empty");
  if (!frame_ || frame_->width_px() != scene.width_px || frame_->height_px() != scene.height_px) {
    frame_ = std::make_unique<GlFrameBuffer>(scene.width_px, scene.height_px);
    blurred_ = std::make_unique<GlFrameBuffer>(scene.width_px, scene.height_px);
  }
  stamp(nullptr);
  load_scene(scene, scene_token);

  // Section 5.1: on the scene, before glare.
  result.frame_luminance_cd_m2 =
      adaptation_.luminance_cd_m2(*frame_, input.gaze_x, input.gaze_y, settings.adaptation_weighting);
  stamp("adaptation");
  if (settings.adaptation) {
    result.adapted_luminance_cd_m2 = eye.advance(result.frame_luminance_cd_m2, input.frame_time_s);
    result.stages_run.push_back(PerceptionStage::adaptation);
  } else {
    result.adapted_luminance_cd_m2 = result.frame_luminance_cd_m2;
  }
  if (settings.glare && glare) {
    glare(scene, *frame_);
    stamp("glare");
    result.stages_run.push_back(PerceptionStage::glare);
  }
  GlFrameBuffer* current = frame_.get();
  if (settings.acuity) {
    acuity_.apply(*current, settings.acuity_settings, display_pixels_per_degree(display), *blurred_);
    current = blurred_.get();
    stamp("acuity");
    result.stages_run.push_back(PerceptionStage::acuity);
  }
  if (settings.tone_mapping) {
    tone_mapping_.apply(*current, result.adapted_luminance_cd_m2, settings.tone_mapping_settings,
                        display.peak_luminance_cd_m2, *current);
    stamp("tone mapping");
    result.stages_run.push_back(PerceptionStage::tone_mapping);
  }
  if (settings.scotopic) {
    const double sigma =
        rod_sensitivity(result.adapted_luminance_cd_m2, settings.adaptation_time_constants.rod_half_sensitivity_cd_m2);
    scotopic_.apply(*current, sigma, settings.scotopic_settings, *current);
    stamp("scotopic");
    result.stages_run.push_back(PerceptionStage::scotopic);
  }
  return *current;
}

}  // namespace glarelab::gl

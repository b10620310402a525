#pragma once
// The perception stages of Luidolt 2020 in the order of its Fig. 6.1 on the GPU, the GL counterpart
// of perception_stages.h's run_perception_stages, with the same switches, settings, validation and
// result: adaptation luminance (GlFrameAdaptationLuminance) -> the temporal filter (Eqs. 5.2-5.4,
// a scalar, on the CPU: TemporalAdaptation) -> glare (the caller's, on the CPU: the frame is read
// back and uploaded again around it) -> acuity loss (GlAcuityLoss) -> tone mapping (GlToneMapping)
// -> scotopic colour (GlScotopicColour). One upload, one read-back per frame (two more with glare).
// run_on_gpu leaves the frame on the GPU instead: its glare hands the glared frame over in a GL
// buffer where it can, and the perceived frame stays in a buffer the caller keeps; the only
// read-back is then the adaptation pyramid's top cells (a reduction of a few values), and a scene
// the caller names by a token (FrameFacts::gpu_scene_token) goes up once for all its frames.
// Requires a current OpenGL 4.5 context; not thread-safe.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "stimuli/perception/gl_acuity_loss.h"
#include "stimuli/perception/gl_frame_adaptation_luminance.h"
#include "stimuli/perception/gl_frame_buffer.h"
#include "stimuli/perception/gl_scotopic_colour.h"
#include "stimuli/perception/gl_tone_mapping.h"
#include "stimuli/perception/perception_stages.h"

namespace glarelab::gl {

class GlPerceptionStages {
 public:
  GlPerceptionStages() = default;

  // As run_perception_stages: throws std::invalid_argument naming the settings group and field,
  // or when `eye` was made with other time constants; advances `eye` when adaptation is on.
  PerceptionResult run(const ImageRGBA& scene, const PerceptionFrameInput& input, TemporalAdaptation& eye,
                       const PerceptionSettings& settings, const DisplaySpec& display,
                       const PerceptionGlare& glare = {});

  // The glare between adaptation and acuity writing the glared scene into `out` (the scene's size),
  // on the GPU where it can (a GL buffer copied, nothing read back), else uploaded from the host.
  using GlareOnGpu = std::function<void(const ImageRGBA& scene, GlFrameBuffer& out)>;
  // run() with the perceived frame left on the GPU, in a buffer made for this frame (`out`, so that
  // frames made ahead of their flips are each kept): `result.image` stays empty. `scene_token`: 0,
  // or a token the caller gives this scene and no other (FrameFacts::gpu_scene_token); the scene
  // last uploaded under the same token is copied on the GPU instead of uploaded again.
  PerceptionResult run_on_gpu(const ImageRGBA& scene, const PerceptionFrameInput& input, TemporalAdaptation& eye,
                              const PerceptionSettings& settings, const DisplaySpec& display, const GlareOnGpu& glare,
                              std::uint64_t scene_token, std::shared_ptr<GlFrameBuffer>& out);
  // How many scenes went up from the host (each run(), each run_on_gpu() with a new token or none).
  std::size_t scene_uploads() const { return scene_uploads_; }

 private:
  // The stages up to the frame's last one; returns the buffer that holds it (frame_ or blurred_).
  GlFrameBuffer& run_stages(const ImageRGBA& scene, const PerceptionFrameInput& input, TemporalAdaptation& eye,
                            const PerceptionSettings& settings, const DisplaySpec& display, const GlareOnGpu& glare,
                            std::uint64_t scene_token, PerceptionResult& result);
  // The scene into frame_: uploaded, or copied from kept_scene_ when it holds the same token's.
  void load_scene(const ImageRGBA& scene, std::uint64_t scene_token);
  GlFrameAdaptationLuminance adaptation_;
  GlAcuityLoss acuity_;
  GlToneMapping tone_mapping_;
  GlScotopicColour scotopic_;
  std::unique_ptr<GlFrameBuffer> frame_, blurred_;  // kept while the frame size stays the same
  // The last scene uploaded under a token, as it came (the stages overwrite frame_).
  std::unique_ptr<GlFrameBuffer> kept_scene_;
  std::uint64_t kept_scene_token_ = 0;
  std::size_t scene_uploads_ = 0;
  // GL_TIMESTAMP queries: one before the first stage and one after each that ran (and after the
  // frame is kept, run_on_gpu), made on first use; read into result.gpu_stages_s at the frame's end.
  std::vector<Query> timestamps_;
  std::vector<const char*> stamped_;  // the stage each query after the first ends
  void stamp(const char* stage_done);
  void read_stamps(PerceptionResult& result);
};

}  // namespace glarelab::gl

#pragma once
// The frame engine seam (docs/ARCHITECTURE.md, "Seams"): what makes one eye's frame. A session
// (run, and render's preview of it) asks it for each eye's frame with that eye's view as it
// reaches the eye (the scene layers in cd/m2 through the condition's spectacles and depth of
// field), the glare mode and the condition's model and refraction (set on its glare stage), the
// perception stages, the gaze and the field luminance; it answers with the composed frame and the
// stages' reports.
//
// Inside, one eye: its glare stage (stimuli/glare_stage.h: its eye model, pupil and blinks) and its
// perception eye (stimuli/session_perception.h: its adaptation), run in the order of Luidolt 2020's
// Fig. 6.1 (adaptation -> glare -> acuity -> tone mapping -> scotopic colour), or the glare alone.
//
// Engines: the CPU engine runs the perception stages on the CPU; the GL engine ("gpu") runs them
// with OpenGL 4.5 (stimuli/perception/gl_perception_stages.h) beside the GL glare backend. The
// spectacle warp and the depth of field run on the CPU in both, before the engine gets the view.
// Asked for (EyeFrameRequest::on_gpu), the GL engine leaves the frame on the GPU: the glare's
// result (wave-optics, hybrid and human eyes; GlareStage::apply_on_gpu) goes from the GL glare
// backend's buffer to the perception stages' (or to the frame's own buffer) by a copy on the GPU, and the perceived frame stays in a buffer the display
// draws from (stimuli/frame_renderer.h); the frame's read-backs are then the adaptation pyramid's
// top cells and each new PSF (core/gl/read_back.h counts them).
// Asked for by name (`[display] engine`, `--engine`: core/frame_engine_request.h), the engine sets
// the glare backend it needs (frame_engine.cpp's table): "gpu" the GL backend, "cpu" a CPU one (the
// float64 reference when [glare] backend = "cpu" names it, else the planned float32 path). "auto"
// follows the one compute choice (engine_glare_backend below: create_glare_backend's table,
// glare/glare_backend.h, asked by [glare] backend or `psf --backend`): a GL glare backend (on a
// hardware GPU with OpenGL 4.5) brings the GL engine, every CPU backend the CPU engine. The choice
// is made when the first frame needs it, so a session whose frames are all shown as composed never
// makes a GL context for it. On a CPU "auto" gives the planned float32 path (glare/cpu/float_glare.h),
// PSFs with the observer's refraction included; "cpu" the float64 reference.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/display_spec.h"
#include "core/frame_engine_request.h"
#include "core/gl/gl_context.h"
#include "core/image.h"
#include "core/perception_settings.h"
#include "core/spelling.h"
#include "glare/glare_spec.h"
#include "stimuli/glare_stage.h"
#include "stimuli/perception/gl_frame_buffer.h"
#include "stimuli/position_glare.h"
#include "stimuli/session_perception.h"

namespace glarelab {

enum class FrameEngineKind { cpu, gl };
inline constexpr Spelling<FrameEngineKind> kFrameEngineKindSpellings[] = {{FrameEngineKind::cpu, "cpu"},
                                                                          {FrameEngineKind::gl, "gl"}};
constexpr std::span<const Spelling<FrameEngineKind>> spellings(FrameEngineKind) { return kFrameEngineKindSpellings; }

// One eye's frame to make. The references must outlive the call.
struct EyeFrameRequest {
  explicit EyeFrameRequest(const ImageRGBA& seen) : seen_cd_m2(seen) {}
  const ImageRGBA& seen_cd_m2;  // the eye's view as it reaches the eye (cd/m2, linear Rec.709)
  GlareMode mode = GlareMode::control;
  // One layer per position when the positions' glare modes differ (stimuli/position_glare.h), with
  // their static glare kept from frame to frame in `static_layers`; empty: `mode` for the frame.
  const std::vector<GlareLayer>* layers = nullptr;
  StaticLayerGlare* static_layers = nullptr;
  bool glared = false;  // false: no glare (a perceived frame may have none)
  // The perception stages; nullptr: the glare alone.
  const PerceptionSettings* perception = nullptr;
  double time_s = 0.0;        // the frame's flip on the session clock
  double frame_time_s = 0.0;  // how long it is shown (Eq. 5.2's ft)
  std::optional<GazePoint> gaze;  // normalised in the eye's view; nothing: its centre
  double field_cd_m2 = 0.0;       // what the eye adapts to without the perception stages
  FrameFacts* facts = nullptr;    // the seen image's, kept from frame to frame (nothing: found afresh)
  // The GL engine may leave the frame on the GPU (EyeFrame::gpu_image_cd_m2) instead of reading it
  // back. Only where every context the engine's GlContextFactory makes is one and the same (a
  // session's: the display's own, so that the display draws the frame from that buffer).
  bool on_gpu = false;
};

struct EyeFrame {
  ImageRGBA image_cd_m2;  // empty when the frame stayed on the GPU
  // The frame on the GPU (EyeFrameRequest::on_gpu, the GL engine: the glare where it stays there,
  // GlareStage::apply_on_gpu, and the perception stages): RGBA32F rows from the top in a GL buffer of the engine's context,
  // one per frame. Else null, and the frame is image_cd_m2.
  std::shared_ptr<gl::GlFrameBuffer> gpu_image_cd_m2;
  std::vector<GlareFrameReport> reports;  // one per glared image (a layer each when the sides differ)
  // With the perception stages: this frame's adaptation luminance (section 5.1) and L_i (Eq. 5.2).
  std::optional<double> frame_luminance_cd_m2;
  std::optional<double> adapted_luminance_cd_m2;
  // The GL engine: each GPU stage's time on the GPU's clock (timer queries), seconds, in the order
  // they ran: the perception stages' ("adaptation", "glare", "acuity", ...) and the convolution's
  // ("convolution image FFT", ...; glare/gl/convolution.h) where the glare ran there. Empty on the CPU.
  std::vector<std::pair<std::string, double>> gpu_stages_s;
};

// The compute choice behind every frame engine: what computes the eye's PSFs and convolves its
// frames for a request, frames of this PSF layout at this display scale (create_glare_backend with
// the frames' layout: "auto" takes GL on a hardware GPU, else the planned float32 path). A session's
// glare stage makes its backend by it, and `glarelab psf` its one PSF, so that the two never differ.
// `named`: false when the request is the caller's default (the reason says so).
GlareBackendChoice engine_glare_backend(GlareBackendRequest request, const GlareFrameLayout& layout,
                                        GlContextFactory gl_context, bool named = true);

// The engine a request takes here, and one sentence why, without making a frame: `glarelab bench
// --engine` (which rows to time). "auto" asks the one compute choice (create_glare_backend) as a
// session's first frame does: the GPU engine on a hardware GPU with OpenGL 4.5, else the CPU engine.
struct FrameEngineChoice {
  FrameEngineKind kind = FrameEngineKind::cpu;
  std::string reason;
};
FrameEngineChoice choose_frame_engine(FrameEngineRequest request, GlContextFactory gl_context);

class FrameEngine {
 public:
  // `seed` seeds the eye model; `gl_context` makes the context GL work runs in (empty: no GL);
  // `request`: the engine asked for (automatic: the one the glare backend brings).
  FrameEngine(const GlareSpec& glare, const AdaptationTimeConstants& time_constants, const DisplaySpec& display,
              std::uint64_t seed, GlContextFactory gl_context,
              FrameEngineRequest request = FrameEngineRequest::automatic);
  ~FrameEngine();
  FrameEngine(const FrameEngine&) = delete;
  FrameEngine& operator=(const FrameEngine&) = delete;

  EyeFrame frame(const EyeFrameRequest& request);

  // The engine, chosen now if not yet (this makes the glare backend), and one sentence why.
  FrameEngineKind kind();
  const std::string& reason();
  FrameEngineRequest request() const { return request_; }
  // Where each stage of a frame runs with this engine, and what goes back to the host: one line
  // for the session's `engine` event ("spectacle warp cpu; depth of field cpu; glare gl; ...").
  std::string stage_backends();

  // The eye's stages, for what is not a frame: the condition's model and refraction, the tracker's
  // pupil and blinks, frames the eye sees without their glare being computed.
  GlareStage& glare() { return glare_; }
  SessionPerception& perception() { return perception_; }

  class Stages;  // how the perception stages run (frame_engine.cpp)

 private:
  Stages& stages();
  FrameEngineRequest request_;
  GlContextFactory gl_context_;
  GlareStage glare_;
  SessionPerception perception_;
  std::unique_ptr<Stages> stages_;
  std::unique_ptr<GpuLayerSum> layer_sum_;  // layered glare on the GPU, made on first use
  FrameEngineKind kind_ = FrameEngineKind::cpu;
  std::string reason_;
};

}  // namespace glarelab

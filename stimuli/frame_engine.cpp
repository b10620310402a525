#include "stimuli/frame_engine.h"

#include <cstdint>
#include <utility>

#include "core/errors.h"
#include "core/image_token.h"
#include "stimuli/perception/gl_perception_stages.h"
#include "stimuli/perception/perception_stages_float.h"

namespace glarelab {

// How an engine runs the perception stages of a frame.
class FrameEngine::Stages {
 public:
  virtual ~Stages() = default;
  virtual PerceptionResult run(const ImageRGBA& scene, const PerceptionFrameInput& input, TemporalAdaptation& eye,
                               const PerceptionSettings& settings, const DisplaySpec& display,
                               const PerceptionGlare& glare) = 0;
  // run() with the perceived frame left on the GPU (`out`), the glare handing its frame over on the
  // GPU where it can; an engine that keeps nothing on a GPU answers with run()'s host image.
  virtual PerceptionResult run_on_gpu(const ImageRGBA& scene, const PerceptionFrameInput& input, TemporalAdaptation& eye,
                                      const PerceptionSettings& settings, const DisplaySpec& display,
                                      const PerceptionGlare& glare, gl::GlFrameBuffer*& glare_out,
                                      std::uint64_t /*scene_token*/, std::shared_ptr<gl::GlFrameBuffer>& /*out*/) {
    glare_out = nullptr;
    return run(scene, input, eye, settings, display, glare);
  }
};

namespace {

class CpuStages final : public FrameEngine::Stages {
 public:
  PerceptionResult run(const ImageRGBA& scene, const PerceptionFrameInput& input, TemporalAdaptation& eye,
                       const PerceptionSettings& settings, const DisplaySpec& display,
                       const PerceptionGlare& glare) override {
    return run_perception_stages_float(scene, input, eye, settings, display, glare);
  }
};

// The stages in a GL context of their own. The glare between adaptation and acuity may be the GL
// glare backend's, which makes its own context current: the stages' is made current again after it.
class GlStages final : public FrameEngine::Stages {
 public:
  explicit GlStages(const GlContextFactory& gl_context) : context_(gl_context()) {
    if (!context_) throw DisplayError("OpenGL: the GL frame engine's perception stages were given no context");
  }
  PerceptionResult run(const ImageRGBA& scene, const PerceptionFrameInput& input, TemporalAdaptation& eye,
                       const PerceptionSettings& settings, const DisplaySpec& display,
                       const PerceptionGlare& glare) override {
    context_->make_current();
    PerceptionGlare in_context;
    if (glare)
      in_context = [&](const ImageRGBA& adapted_cd_m2) {
        ImageRGBA glared = glare(adapted_cd_m2);
        context_->make_current();
        return glared;
      };
    return stages_.run(scene, input, eye, settings, display, in_context);
  }
  // `glare` (the session's, through SessionPerception) writes its frame into `glare_out` on the GPU
  // where it can and returns an empty image, else returns the glared image, which is uploaded.
  PerceptionResult run_on_gpu(const ImageRGBA& scene, const PerceptionFrameInput& input, TemporalAdaptation& eye,
                              const PerceptionSettings& settings, const DisplaySpec& display,
                              const PerceptionGlare& glare, gl::GlFrameBuffer*& glare_out, std::uint64_t scene_token,
                              std::shared_ptr<gl::GlFrameBuffer>& out) override {
    context_->make_current();
    gl::GlPerceptionStages::GlareOnGpu on_gpu;
    if (glare)
      on_gpu = [&](const ImageRGBA& adapted_cd_m2, gl::GlFrameBuffer& into) {
        glare_out = &into;
        const ImageRGBA glared = glare(adapted_cd_m2);
        glare_out = nullptr;
        context_->make_current();
        if (!glared.empty()) into.upload(glared);
      };
    return stages_.run_on_gpu(scene, input, eye, settings, display, on_gpu, scene_token, out);
  }

 private:
  std::unique_ptr<GlContext> context_;
  gl::GlPerceptionStages stages_;
};

// The engines, in the order "auto" tries them: each takes the frames of the compute backends it
// serves (the one choice of compute, create_glare_backend). Asked for by name, an engine sets the
// glare backend it needs from the one [glare] backend asks for, and whether its glare may use GL.
struct EngineCandidate {
  FrameEngineKind kind;
  FrameEngineRequest answers;
  bool (*serves)(GlareBackendKind);
  GlareBackendRequest (*glare_backend)(GlareBackendRequest asked);
  bool glare_on_gl;
  std::unique_ptr<FrameEngine::Stages> (*make)(const GlContextFactory&);
  const char* why;
  const char* perception_backend;  // where its perception stages run, for the engine event
  // What goes back to the host after each frame's GPU work (nullptr: nothing runs on a GPU).
  const char* read_back;
};
constexpr EngineCandidate kEngines[] = {
    {FrameEngineKind::gl, FrameEngineRequest::gpu, [](GlareBackendKind kind) { return kind == GlareBackendKind::gl; },
     [](GlareBackendRequest) { return GlareBackendRequest::gl; }, true,
     [](const GlContextFactory& gl_context) -> std::unique_ptr<FrameEngine::Stages> {
       return std::make_unique<GlStages>(gl_context);
     },
     "the glare runs on OpenGL, so the perception stages do too (stimuli/perception/gl_perception_stages.h)",
     "gl (stimuli/perception/gl_perception_stages.h)",
     "in a session none of the frame for the wave-optics, hybrid and human eyes' glare and the perception "
     "stages: they stay on the GPU, in the display's context, and the display draws them; what comes back is "
     "each new PSF and the adaptation pyramid's top cells (core/gl/read_back.h); the hybrid and human eyes' far "
     "part and halo are made on the host once per composed frame and uploaded; the analytic models, a gaze "
     "window, a gain other than 1, source excess and a layer keeping its peak are made on the host"},
    // [glare] backend = "cpu" keeps the float64 reference; "auto" and "gl" give the planned float32
    // path (no GL for its glare).
    {FrameEngineKind::cpu, FrameEngineRequest::cpu, [](GlareBackendKind) { return true; },
     [](GlareBackendRequest asked) {
       return asked == GlareBackendRequest::cpu ? GlareBackendRequest::cpu : GlareBackendRequest::automatic;
     },
     false, [](const GlContextFactory&) -> std::unique_ptr<FrameEngine::Stages> { return std::make_unique<CpuStages>(); },
     "the glare runs on the CPU, so the perception stages do too (stimuli/perception/perception_stages_float.h)",
     "cpu float32 (stimuli/perception/perception_stages_float.h)", nullptr},
};

// The engine a request names (nullptr for "auto", which the glare backend decides).
const EngineCandidate* named_engine(FrameEngineRequest request) {
  for (const EngineCandidate& candidate : kEngines)
    if (request != FrameEngineRequest::automatic && candidate.answers == request) return &candidate;
  return nullptr;
}

GlareSpec engine_glare_spec(GlareSpec glare, FrameEngineRequest request) {
  if (const EngineCandidate* engine = named_engine(request)) glare.backend = engine->glare_backend(glare.backend);
  return glare;
}

GlContextFactory engine_gl_context(GlContextFactory gl_context, FrameEngineRequest request) {
  const EngineCandidate* engine = named_engine(request);
  if (engine != nullptr && !engine->glare_on_gl) return {};
  return gl_context;
}

}  // namespace

GlareBackendChoice engine_glare_backend(GlareBackendRequest request, const GlareFrameLayout& layout,
                                        GlContextFactory gl_context, bool named) {
  GlareBackendSettings settings;
  settings.gl_context = std::move(gl_context);
  settings.grid_px = layout.psf.grid_px;
  settings.frames = layout;
  settings.named = named;
  return create_glare_backend(request, settings);
}

FrameEngineChoice choose_frame_engine(FrameEngineRequest request, GlContextFactory gl_context) {
  FrameEngineChoice choice;
  if (const EngineCandidate* named = named_engine(request)) {
    choice.kind = named->kind;
    choice.reason = "engine " + std::string(spelling(request)) + ": asked for by name; " + named->why + ".";
    return choice;
  }
  const GlareBackendChoice backend =
      create_glare_backend(GlareBackendRequest::automatic, {.gl_context = std::move(gl_context)});
  for (const EngineCandidate& candidate : kEngines) {
    if (!candidate.serves(backend.kind)) continue;
    choice.kind = candidate.kind;
    choice.reason = "engine auto picked frame engine " + std::string(spelling(candidate.kind)) + ": " + backend.reason;
    break;
  }
  return choice;
}

FrameEngine::FrameEngine(const GlareSpec& glare, const AdaptationTimeConstants& time_constants,
                         const DisplaySpec& display, std::uint64_t seed, GlContextFactory gl_context,
                         FrameEngineRequest request)
    : request_(request),
      gl_context_(gl_context),
      glare_(engine_glare_spec(glare, request), display, seed, engine_gl_context(std::move(gl_context), request)),
      perception_(time_constants, display) {}

FrameEngine::~FrameEngine() = default;

FrameEngine::Stages& FrameEngine::stages() {
  if (stages_) return *stages_;
  const GlareBackendKind backend = glare_.backend().kind();
  const EngineCandidate* named = named_engine(request_);
  for (const EngineCandidate& candidate : kEngines) {
    if (named != nullptr ? &candidate != named : !candidate.serves(backend)) continue;
    stages_ = candidate.make(gl_context_);
    kind_ = candidate.kind;
    reason_ = "frame engine " + std::string(spelling(kind_)) + ": glare backend " + std::string(spelling(backend)) +
              "; " + candidate.why + "; " +
              (named != nullptr ? "engine " + std::string(spelling(request_)) + " asked for by name ([display] engine or --engine)"
                                : std::string("engine auto: the one its glare backend brings")) +
              ".";
    break;
  }
  return *stages_;
}

std::string FrameEngine::stage_backends() {
  stages();
  const EngineCandidate* engine = nullptr;
  for (const EngineCandidate& candidate : kEngines)
    if (candidate.kind == kind_) engine = &candidate;
  std::string text = "spectacle warp cpu; depth of field cpu; glare " + std::string(spelling(glare_.backend().kind())) +
                     "; perception stages " + engine->perception_backend +
                     "; overlays and display encoding on the display's renderer";
  text += engine->read_back != nullptr ? std::string("; read back: ") + engine->read_back
                                       : std::string("; read back: nothing (the frame is made on the host)");
  return text;
}

FrameEngineKind FrameEngine::kind() {
  stages();
  return kind_;
}

const std::string& FrameEngine::reason() {
  stages();
  return reason_;
}

EyeFrame FrameEngine::frame(const EyeFrameRequest& request) {
  EyeFrame result;
  const bool on_gpu = request.on_gpu && kind() == FrameEngineKind::gl;
  // The seen image's token on the GPU, made once for its facts: the frames of an interval upload it
  // once, and the glare's convolution knows its spectrum without comparing its pixels.
  std::uint64_t scene_token = 0;
  if (on_gpu && request.facts != nullptr) {
    if (request.facts->gpu_scene_token == 0) request.facts->gpu_scene_token = new_image_token();
    scene_token = request.facts->gpu_scene_token;
  }
  // On the GPU: where the glare of the frame goes when it stays there (the perception stages'
  // buffer; nullptr: the glare's own frame, made here).
  gl::GlFrameBuffer* glare_out = nullptr;
  // The glare of the image left on the GPU where the glare stage can (a wave-optics model whole,
  // GlareStage::apply_on_gpu): copied into `into` there, or into a buffer of the frame's own, and an
  // empty image returned; else the glared image.
  const auto glare_on_gpu = [&](const ImageRGBA& image_cd_m2, std::optional<double> field_cd_m2, FrameFacts* facts,
                                gl::GlFrameBuffer* into) -> ImageRGBA {
    GlareFrameReport report;
    GlareStage::GlaredOnGpu glared = glare_.apply_on_gpu(image_cd_m2, request.mode, request.time_s, &report,
                                                         request.gaze, field_cd_m2.value_or(request.field_cd_m2), facts);
    result.reports.push_back(report);
    if (glared.gpu_buffer == 0) return std::move(glared.image);
    for (const auto& [stage, seconds] : glare_.backend().last_gpu_stages_s())
      result.gpu_stages_s.emplace_back("convolution " + stage, seconds);
    if (into == nullptr) {
      result.gpu_image_cd_m2 = std::make_shared<gl::GlFrameBuffer>(image_cd_m2.width_px, image_cd_m2.height_px);
      into = result.gpu_image_cd_m2.get();
    }
    into->copy_from(glared.gpu_buffer);
    return {};
  };
  // The glare of an image on the eye adapted to `field_cd_m2` (nothing: the image's mean
  // luminance); `facts`: the seen image's, for that image only.
  const auto glare_of = [&](const ImageRGBA& image_cd_m2, std::optional<double> field_cd_m2, FrameFacts* facts) {
    const bool layered = request.layers != nullptr && !request.layers->empty();
    if (on_gpu && !layered) return glare_on_gpu(image_cd_m2, field_cd_m2, facts, glare_out);
    if (on_gpu) {
      if (!layer_sum_) layer_sum_ = std::make_unique<GpuLayerSum>();
      std::shared_ptr<gl::GlFrameBuffer> glared =
          apply_layered_glare_on_gpu(glare_, *layer_sum_, image_cd_m2, *request.layers, request.time_s, request.gaze,
                                     &result.reports, field_cd_m2, request.static_layers);
      if (glared) {
        if (glare_out != nullptr) {
          glare_out->copy_from(glared->buffer());
        } else {
          result.gpu_image_cd_m2 = std::move(glared);
        }
        return ImageRGBA();
      }
    }
    if (layered)
      return apply_layered_glare(glare_, image_cd_m2, *request.layers, request.time_s, request.gaze, &result.reports,
                                 field_cd_m2, request.static_layers);
    GlareFrameReport report;
    ImageRGBA glared = glare_.apply(image_cd_m2, request.mode, request.time_s, &report, request.gaze,
                                    field_cd_m2.value_or(request.field_cd_m2), facts);
    result.reports.push_back(report);
    return glared;
  };
  if (request.perception == nullptr) {
    result.image_cd_m2 = glare_of(request.seen_cd_m2, request.field_cd_m2, request.facts);
    return result;
  }
  const GazePoint gaze = request.gaze.value_or(GazePoint{});
  // The stages hand the glare the seen image itself (Luidolt 2020 Fig. 6.1: adaptation measures it,
  // glare spreads it), whose facts the request brings; any other image is found afresh.
  const FieldGlare stage_glare = [&](const ImageRGBA& adapted_cd_m2, std::optional<double> field_cd_m2) {
    return glare_of(adapted_cd_m2, field_cd_m2, &adapted_cd_m2 == &request.seen_cd_m2 ? request.facts : nullptr);
  };
  Stages& engine = stages();
  std::shared_ptr<gl::GlFrameBuffer> perceived_on_gpu;
  const PerceptionStagesRun run = [&](const ImageRGBA& scene, const PerceptionFrameInput& input,
                                      TemporalAdaptation& eye, const PerceptionSettings& settings,
                                      const DisplaySpec& display, const PerceptionGlare& glare) {
    // The token names the seen image: a scene the stages get instead (none today) is uploaded.
    if (on_gpu)
      return engine.run_on_gpu(scene, input, eye, settings, display, glare, glare_out,
                               &scene == &request.seen_cd_m2 ? scene_token : 0, perceived_on_gpu);
    return engine.run(scene, input, eye, settings, display, glare);
  };
  PerceptionResult stages_result =
      perception_.process(request.seen_cd_m2, *request.perception, request.time_s, request.frame_time_s, gaze.x, gaze.y,
                          request.glared ? stage_glare : FieldGlare(), run);
  result.image_cd_m2 = std::move(stages_result.image);
  result.gpu_image_cd_m2 = std::move(perceived_on_gpu);
  result.gpu_stages_s.insert(result.gpu_stages_s.begin(), stages_result.gpu_stages_s.begin(),
                             stages_result.gpu_stages_s.end());
  result.frame_luminance_cd_m2 = stages_result.frame_luminance_cd_m2;
  result.adapted_luminance_cd_m2 = stages_result.adapted_luminance_cd_m2;
  return result;
}

}  // namespace glarelab

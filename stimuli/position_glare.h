#pragma once
// Glare that differs between the positions of one frame. Ritschel et al. 2009, section 6.1, shows
// "two images of the same scene where each of the displays was either enhanced by application of
// dynamic or static glare or not": one frame, a glare condition per side. The composed frame is
// split into one layer per position (its placement alone, zero elsewhere) and the background part
// (composed minus the layers); each layer is convolved with the PSF of its own mode, the eye
// adapted to the whole frame's mean luminance (one eye sees the whole display), and the results
// are summed with the background part, which is left as it is (exact for the usual black
// background; for a uniform background a unit-sum PSF changes it only at the layers' edges).
// Convolution is linear, so layers sharing one mode give the whole-frame glare of that mode.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/image.h"
#include "stimuli/glare_stage.h"
#include "stimuli/perception/gl_frame_buffer.h"

namespace glarelab {

struct GlareLayer {
  ImageRGBA image_cd_m2;  // the position's placement alone on zero, frame-sized
  GlareMode mode = GlareMode::control;
  // Keep the layer's brightest pixel where it was before glare: the glared layer is scaled by
  // (peak before) / (peak after). Glare (frame + gain (glared - frame), clipped at 0) is
  // homogeneous in the frame, so this is the glare of the layer drawn that much brighter: Spencer
  // et al. 1995, section 4, "the maximum intensity of the source with the corona flare was 75% of
  // the maximum value displayable" -- the source is as bright as it must be for its glared image
  // to peak at the drawn peak. (A point-spread function moves some of a source's light into its
  // halo, the more the higher the glare gain, so the unscaled core would dim as the glare grows.)
  bool keep_peak = false;
  // The layer image's facts, found on its first frame and kept for the others (the image does not
  // change while the layer lives). Mutable: a cache the const layers of a frame fill.
  mutable FrameFacts facts = {};
};

// The glare of an interval's static layers, kept between its frames: a static layer's glare is a
// function of the layer, the frozen eye, the field luminance and the gaze, none of which changes
// from frame to frame unless a tracker moves the gaze (or the perception stages the adaptation),
// so a dynamic source beside a static one does not convolve the static one again every frame.
// One cache per interval (the layers it was filled for).
struct StaticLayerGlare {
  struct Kept {
    ImageRGBA glared_cd_m2;  // after keep_peak
    GlareFrameReport report;
    std::optional<GazePoint> gaze;
    double field_luminance_cd_m2 = 0.0;
    // The glare on the GPU (apply_layered_glare_on_gpu), where glared_cd_m2 is empty.
    std::shared_ptr<gl::GlFrameBuffer> glared_on_gpu;
    std::uint64_t serial = 0;  // unique to each filling (the base below names what it holds)
  };
  std::vector<std::optional<Kept>> layers;  // by layer index
  // The part of the layers' sum that is the same on every frame of the interval: per value the
  // composed frame less each glaring layer, plus the kept glare of the glaring layers before the
  // first one glared anew, in the sum's order (apply_layered_glare). A frame then adds the other
  // layers' glare to it: the same operations in the same order as the whole sum, so the same bits,
  // reading two or three frames where the sum reads five (the demo: a dynamic lamp beside a static
  // one).
  struct SumBase {
    ImageRGBA partial_cd_m2;
    const float* composed = nullptr;  // the composed frame it was made from
    std::vector<std::size_t> glaring;  // the glaring layers, in order
    std::vector<std::uint64_t> kept_serials;  // the kept glares added, the first glaring layers'
  };
  SumBase base;
};

// One glared frame at `time_s`. `reports` receives one report per layer that is not control.
// `field_luminance_cd_m2`: what the eye adapts to (the perception stages' adapted luminance);
// nothing: the whole frame's mean luminance. `kept`: the interval's static layers' glare, reused
// where the gaze and field luminance are those it was computed for (the same result, bit for bit)
// and filled otherwise. Throws std::invalid_argument when a layer's size differs from the
// composed frame's.
ImageRGBA apply_layered_glare(GlareStage& stage, const ImageRGBA& composed_cd_m2, const std::vector<GlareLayer>& layers,
                              double time_s, const std::optional<GazePoint>& gaze,
                              std::vector<GlareFrameReport>* reports = nullptr,
                              std::optional<double> field_luminance_cd_m2 = std::nullopt,
                              StaticLayerGlare* kept = nullptr);

// apply_layered_glare with the frame left on the GPU (the GL engine, stimuli/frame_engine.h): each
// glaring layer glared by GlareStage::apply_on_gpu (its host result uploaded where it has one), and
// the sum made on the GPU (stimuli/shaders/layer_glare_sum.comp) into a buffer made for this frame;
// static layers' glare kept on the GPU. The stage's GL context must be current and shared with the
// caller's. Nothing (the caller glares on the host) when a layer keeps its peak (its scale needs
// the glared layer's maximum).
// The sum's pass (stimuli/shaders/layer_glare_sum.comp: frame += glared layer - layer), its program
// made on first use in the current context. Requires that context current whenever it is used or
// destroyed; not thread-safe.
class GpuLayerSum {
 public:
  void add(gl::GlFrameBuffer& frame, const gl::GlFrameBuffer& layer, const gl::GlFrameBuffer& glared);

 private:
  gl::Program program_;
};
std::shared_ptr<gl::GlFrameBuffer> apply_layered_glare_on_gpu(GlareStage& stage, GpuLayerSum& sum,
                                                              const ImageRGBA& composed_cd_m2,
                                                              const std::vector<GlareLayer>& layers, double time_s,
                                                              const std::optional<GazePoint>& gaze,
                                                              std::vector<GlareFrameReport>* reports,
                                                              std::optional<double> field_luminance_cd_m2,
                                                              StaticLayerGlare* kept);

}  // namespace glarelab

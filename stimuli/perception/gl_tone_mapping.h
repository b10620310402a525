#pragma once
// Tone mapping with the adapted luminance (Luidolt 2020, sections 3.4 and 6.1) on the GPU, the GL
// counterpart of tone_mapping.h's tone_map (Narkowicz's or Hill's ACES fit with L_a as middle grey,
// or the clip; shaders/tone_mapping.comp). The exposure 0.18 [x 0.6] / max(L_a, floor) is the
// reference's own (tone_mapping_exposure_per_cd_m2), computed in double on the host.
// Requires a current OpenGL 4.5 context; not thread-safe.
#include "core/gl/gl_objects.h"
#include "core/perception_settings.h"
#include "stimuli/perception/gl_frame_buffer.h"

namespace glarelab::gl {

class GlToneMapping {
 public:
  GlToneMapping();

  // Scene cd/m2 in, display cd/m2 (0 .. peak) out, alpha kept; `output` may be `input`. Throws
  // std::invalid_argument("perception tone mapping: ...") as tone_map does, or for mismatched sizes.
  void apply(const GlFrameBuffer& input, double adapted_luminance_cd_m2, const ToneMappingSettings& settings,
             double peak_luminance_cd_m2, GlFrameBuffer& output);

 private:
  Program program_;
};

}  // namespace glarelab::gl

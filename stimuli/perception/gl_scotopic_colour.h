#pragma once
// Scotopic colour (Luidolt 2020, section 5.4) on the GPU, the GL counterpart of scotopic_colour.h's
// apply_scotopic_colour: Eq. 5.18's tint or Spencer 1995's desaturation, weighted by the rod
// sensitivity of the adapted luminance (shaders/scotopic_colour.comp).
// Requires a current OpenGL 4.5 context; not thread-safe.
#include "core/gl/gl_objects.h"
#include "core/perception_settings.h"
#include "stimuli/perception/gl_frame_buffer.h"

namespace glarelab::gl {

class GlScotopicColour {
 public:
  GlScotopicColour();

  // Display cd/m2 in and out, alpha kept; rod_sensitivity in [0, 1] (Eq. 5.4 at L_i); `output` may
  // be `input`. Throws std::invalid_argument("perception scotopic: ...") as the reference does, or
  // for mismatched sizes.
  void apply(const GlFrameBuffer& input, double rod_sensitivity, const ScotopicSettings& settings,
             GlFrameBuffer& output);

 private:
  Program program_;
};

}  // namespace glarelab::gl

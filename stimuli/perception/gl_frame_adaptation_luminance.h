#pragma once
// The adaptation luminance of one frame (Luidolt 2020, section 5.1, Eq. 5.1) on the GPU, the GL
// counterpart of frame_adaptation_luminance.h (whose comment gives the method and its reasons):
// gaze Gaussian times Eq. 5.1's luminance, area resampling to resampled_size_px squared
// (shaders/adaptation_resample.comp), the Gaussian pyramid to top_level_size_px squared
// (shaders/adaptation_pyramid.comp), then mean(w Y) / mean(w) of the top level, summed on the host
// in double (a few hundred values; the scalar goes to the CPU's temporal filter, Eqs. 5.2-5.4,
// anyway). Agrees with the double reference to about 1e-6 relative (docs/PERCEPTION.md).
// Requires a current OpenGL 4.5 context; not thread-safe.
#include <vector>

#include "core/gl/gl_objects.h"
#include "core/perception_settings.h"
#include "stimuli/perception/gl_frame_buffer.h"

namespace glarelab::gl {

class GlFrameAdaptationLuminance {
 public:
  GlFrameAdaptationLuminance();

  // cd/m2. Gaze in normalised display coordinates (0..1, top left, y down). Throws
  // std::invalid_argument("perception adaptation: ...") for a non-finite gaze or bad weighting,
  // as the CPU reference does.
  double luminance_cd_m2(const GlFrameBuffer& frame, double gaze_x, double gaze_y,
                         const AdaptationWeighting& weighting = {});

 private:
  Program resample_program_, pyramid_program_;
  Buffer level_a_, level_b_;
  int allocated_cells_ = 0;
};

}  // namespace glarelab::gl

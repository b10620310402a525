#pragma once
// Loss of visual acuity in the dark (Luidolt 2020, section 5.3, Eqs. 5.14-5.17) on the GPU, the GL
// counterpart of acuity_loss.h's apply_acuity_loss (whose comment gives the method and its reasons):
// CIE L*a*b* with the reference white Y_n (shaders/acuity_to_lab.comp), the separable blur of L* with
// each pixel's sigma from its lightness, horizontal then vertical, and back to linear Rec.709 with
// a* and b* kept (shaders/acuity_blur.comp). Same settings (AcuitySettings), same pixels per degree.
// Float32 with the care described in the shaders; agreement with the double reference in
// docs/PERCEPTION.md. Requires a current OpenGL 4.5 context; not thread-safe.
#include "core/gl/gl_objects.h"
#include "core/perception_settings.h"
#include "stimuli/perception/gl_frame_buffer.h"

namespace glarelab::gl {

class GlAcuityLoss {
 public:
  GlAcuityLoss();

  // Writes the blurred frame (cd/m2, alpha kept) into `output`, which must have the input's size.
  // Throws std::invalid_argument("perception acuity: ...") for bad settings or pixels per degree
  // (the reference's checks) or mismatched sizes. `output` may not be `input`.
  void apply(const GlFrameBuffer& input, const AcuitySettings& settings, double pixels_per_degree,
             GlFrameBuffer& output);

 private:
  Program to_lab_program_, blur_program_;
  Buffer lab_, lightness_;
  long long allocated_pixels_ = 0;
};

}  // namespace glarelab::gl

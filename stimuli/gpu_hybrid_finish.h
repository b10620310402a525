#pragma once
// The hybrid and human eyes' frame finished on the GPU (stimuli/glare_stage_hybrid.cpp): the near
// part's convolution left there by the GL glare backend (GlareBackend::convolve_on_gpu) joined with
// the far part's glare and the lenticular halo's ring, which are made on the host once per composed
// frame and uploaded once per composed frame (its token), and turned back into luminance by the
// pixels' solid angles (uploaded once per frame size): stimuli/shaders/hybrid_finish.comp. Nothing
// is read back. Requires the GL context the backend works in to be current whenever it is used or
// destroyed; not thread-safe.
#include <cstdint>

#include "core/gl/gl_objects.h"
#include "core/image.h"
#include "glare/analytic/pixel_solid_angle.h"

namespace glarelab {

class GpuHybridFinish {
 public:
  // The finished frame (cd/m2, RGBA32F, ImageRGBA's layout) in a buffer of this object's, valid
  // until its next call: near_buffer (energies, the frame's size) + far + halo_energy (ring - energy)
  // where `ring` is given, over `solid_angle`. `token` names the composed frame `energy`, `far` and
  // `ring` belong to (GlareStage's kept state): they are uploaded when it changes.
  GLuint finish(GLuint near_buffer, const ImageRGBA& energy, const ImageRGBA& far, const ImageRGBA* ring,
                double halo_energy, const PixelSolidAngle& solid_angle, std::uint64_t token);

 private:
  gl::Program program_;
  gl::Buffer energy_, far_, ring_, weight_, result_;
  std::uint64_t uploaded_token_ = 0, ring_token_ = 0;
  const PixelSolidAngle* weighed_ = nullptr;  // the solid angles weight_ holds
  int width_px_ = 0, height_px_ = 0;
};

}  // namespace glarelab

#pragma once
// A frame on the GPU for the GL perception stages (gl_*.h beside this file): width x height pixels
// of RGBA32F in a std430 shader storage buffer of vec4, row-major, row 0 at the top, the layout of
// ImageRGBA (core/image.h), so upload and download are plain copies. Values are linear Rec.709 in
// cd/m2 (scene or display, as the stage says).
// Requires a current OpenGL 4.5 context (core/gl/gl_context.h); not thread-safe.
#include "core/gl/gl_objects.h"
#include "core/image.h"

namespace glarelab::gl {

class GlFrameBuffer {
 public:
  // An uninitialised frame; throws std::invalid_argument("perception GL: ...") for a size < 1 or a
  // frame above GL_MAX_SHADER_STORAGE_BLOCK_SIZE (at least 3840 x 2160 fits everywhere).
  GlFrameBuffer(int width_px, int height_px);
  // Uploads the frame; throws std::invalid_argument for an empty one.
  explicit GlFrameBuffer(const ImageRGBA& frame);

  int width_px() const { return width_px_; }
  int height_px() const { return height_px_; }
  GLuint buffer() const { return buffer_.get(); }

  void upload(const ImageRGBA& frame);  // same size, else std::invalid_argument
  ImageRGBA download() const;           // waits for the GPU (a counted read-back, core/gl/read_back.h)
  // Copies a buffer of this frame's size and layout (another frame's, or the GL glare backend's
  // result: GlareBackend::convolve_on_gpu) on the GPU; nothing comes to the host.
  void copy_from(GLuint source_buffer);

 private:
  int width_px_;
  int height_px_;
  Buffer buffer_;
};

// Work groups of 16 x 16 invocations cover a width x height frame (the per-pixel shaders of
// stimuli/perception/shaders/ declare local_size_x = local_size_y = 16).
constexpr GLuint kPerceptionTile = 16;
void dispatch_per_pixel(int width_px, int height_px);

}  // namespace glarelab::gl

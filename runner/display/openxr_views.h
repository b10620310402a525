#pragma once
// The OpenGL half of the OpenXR display (runner/display/openxr_display.cpp): each eye's half of the
// side-by-side frame copied into its view's swapchain image, and an image read back on the client
// side. No OpenXR types here: the swapchain images are plain GL textures.
#include <glad/gl.h>

#include "core/gl/gl_objects.h"
#include "core/image.h"

namespace glarelab {

class OpenXrViewCopier {
 public:
  // Builds the copy program (runner/display/openxr_view.frag); the display's context is current.
  OpenXrViewCopier();

  // Takes the default framebuffer's back buffer (width_px x height_px, both eyes side by side) as
  // the frame the views are copied from. Called once per present(), before the buffer swap.
  void take_frame(int width_px, int height_px);
  // Writes the frame's columns [left_px, left_px + width_px) into `image` (a swapchain texture of
  // width_px x height_px). to_linear: the image is float, linear to the runtime (openxr_view.frag).
  // The GL state the session's renderer set (program, framebuffers, viewport, texture unit 0,
  // vertex array, sRGB writes, blending, scissor) is as it was afterwards.
  void copy_view(GLuint image, int left_px, int width_px, int height_px, bool to_linear);

  // The image's drive values, row 0 at the top (a float image encoded back with the sRGB curve).
  static ImageRGBA read_view(GLuint image, int width_px, int height_px, bool from_linear);

 private:
  gl::Program program_;
  gl::VertexArray vertex_array_;
  gl::Framebuffer target_;
  gl::Texture frame_;
  int frame_width_px_ = 0;
  int frame_height_px_ = 0;
  GLint left_px_location_ = -1;
  GLint to_linear_location_ = -1;
};

}  // namespace glarelab

#pragma once
// The OpenGL half of the OpenXR display (runner/display/openxr_display.cpp): the float frame the
// session draws into, each eye's half of it copied into its view's swapchain image, the frame
// shown in the mirror window, and an image read back on the client side. No OpenXR types here: the swapchain images are plain GL textures.
#include <glad/gl.h>

#include "core/gl/gl_objects.h"
#include "core/image.h"

namespace glarelab {

class OpenXrViewCopier {
 public:
  // The side-by-side frame (width_px x height_px, both eyes) the session draws into, and the copy
  // program (runner/display/openxr_view.frag); the display's context is current.
  OpenXrViewCopier(int width_px, int height_px);

  // The frame's framebuffer (DisplayBackend::frame_framebuffer): RGBA32F, so the drive values the
  // session encodes reach the views as computed, not through the mirror window's 8 bits.
  GLuint frame_framebuffer() const { return framebuffer_.get(); }
  // Writes the frame's columns [left_px, left_px + width_px) into `image` (a swapchain texture of
  // width_px x height_px). to_linear: the image is float, linear to the runtime (openxr_view.frag).
  // The GL state the session's renderer set (program, framebuffers, viewport, texture unit 0,
  // vertex array, sRGB writes, blending, scissor) is as it was afterwards.
  void copy_view(GLuint image, int left_px, int width_px, int height_px, bool to_linear);
  // Shows the frame in the default framebuffer (the mirror window, mirror_width_px x
  // mirror_height_px), scaled if the window manager gave the mirror another size.
  void show_in_mirror(int mirror_width_px, int mirror_height_px);

  // The image's drive values, row 0 at the top (a float image encoded back with the sRGB curve).
  static ImageRGBA read_view(GLuint image, int width_px, int height_px, bool from_linear);

 private:
  int width_px_;
  int height_px_;
  gl::Texture frame_;
  gl::Framebuffer framebuffer_;
  gl::Program program_;
  gl::VertexArray vertex_array_;
  gl::Framebuffer target_;
  GLint left_px_location_ = -1;
  GLint to_linear_location_ = -1;
};

}  // namespace glarelab

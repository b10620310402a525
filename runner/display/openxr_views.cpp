#include "runner/display/openxr_views.h"

#include <cmath>

#include "core/errors.h"
#include "core/gl/read_back.h"
#include "core/gl/shader_program.h"

namespace glarelab {
namespace {

// The GL state copy_view changes, put back as the session's renderer left it.
class SavedGlState {
 public:
  SavedGlState() {
    glGetIntegerv(GL_CURRENT_PROGRAM, &program_);
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_framebuffer_);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_framebuffer_);
    glGetIntegerv(GL_VIEWPORT, viewport_);
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vertex_array_);
    glGetIntegerv(GL_ACTIVE_TEXTURE, &active_texture_);
    glActiveTexture(GL_TEXTURE0);
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &texture_);
    srgb_ = glIsEnabled(GL_FRAMEBUFFER_SRGB);
    blend_ = glIsEnabled(GL_BLEND);
    scissor_ = glIsEnabled(GL_SCISSOR_TEST);
  }
  ~SavedGlState() {
    glUseProgram(static_cast<GLuint>(program_));
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(draw_framebuffer_));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(read_framebuffer_));
    glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
    glBindVertexArray(static_cast<GLuint>(vertex_array_));
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(texture_));
    glActiveTexture(static_cast<GLenum>(active_texture_));
    set(GL_FRAMEBUFFER_SRGB, srgb_);
    set(GL_BLEND, blend_);
    set(GL_SCISSOR_TEST, scissor_);
  }
  SavedGlState(const SavedGlState&) = delete;
  SavedGlState& operator=(const SavedGlState&) = delete;

 private:
  static void set(GLenum capability, GLboolean on) {
    if (on) glEnable(capability); else glDisable(capability);
  }
  GLint program_ = 0, draw_framebuffer_ = 0, read_framebuffer_ = 0, vertex_array_ = 0, active_texture_ = 0,
        texture_ = 0;
  GLint viewport_[4] = {0, 0, 0, 0};
  GLboolean srgb_ = GL_FALSE, blend_ = GL_FALSE, scissor_ = GL_FALSE;
};

// IEC 61966-2-1 sRGB encoding of a linear value: the inverse of openxr_view.frag's decode.
float srgb_encode(float linear) {
  const double v = std::fmin(std::fmax(static_cast<double>(linear), 0.0), 1.0);
  return static_cast<float>(v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055);
}

}  // namespace

OpenXrViewCopier::OpenXrViewCopier(int width_px, int height_px)
    : width_px_(width_px),
      height_px_(height_px),
      frame_(gl::create_texture(GL_TEXTURE_2D)),
      framebuffer_(gl::create_framebuffer()),
      program_(gl::build_program({"stimuli/shaders/fullscreen.vert", "runner/display/openxr_view.frag"})),
      vertex_array_(gl::create_vertex_array()),
      target_(gl::create_framebuffer()) {
  // 32-bit float, as the offscreen displays' buffers: the encoded drive values are kept as the
  // encode computed them (no 8-bit window in between), so each view gets them to the precision
  // of its swapchain format.
  glTextureStorage2D(frame_.get(), 1, GL_RGBA32F, width_px, height_px);
  glTextureParameteri(frame_.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(frame_.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glNamedFramebufferTexture(framebuffer_.get(), GL_COLOR_ATTACHMENT0, frame_.get(), 0);
  if (glCheckNamedFramebufferStatus(framebuffer_.get(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw DisplayError("OpenXR: the float frame's framebuffer is incomplete");
  const float black[4] = {0.0f, 0.0f, 0.0f, 1.0f};
  glClearNamedFramebufferfv(framebuffer_.get(), GL_COLOR, 0, black);
  left_px_location_ = glGetUniformLocation(program_.get(), "left_px");
  to_linear_location_ = glGetUniformLocation(program_.get(), "to_linear");
  gl::check_gl_error("OpenXR: making the float frame");
}

void OpenXrViewCopier::show_in_mirror(int mirror_width_px, int mirror_height_px) {
  const SavedGlState saved;
  glDisable(GL_FRAMEBUFFER_SRGB);  // the drive values as they are, as a window shows its frame
  glDisable(GL_SCISSOR_TEST);
  const bool same = mirror_width_px == width_px_ && mirror_height_px == height_px_;
  glBlitNamedFramebuffer(framebuffer_.get(), 0, 0, 0, width_px_, height_px_, 0, 0, mirror_width_px, mirror_height_px,
                         GL_COLOR_BUFFER_BIT, same ? GL_NEAREST : GL_LINEAR);
  gl::check_gl_error("OpenXR: showing the frame in the mirror window");
}

void OpenXrViewCopier::copy_view(GLuint image, int left_px, int width_px, int height_px, bool to_linear) {
  const SavedGlState saved;
  glNamedFramebufferTexture(target_.get(), GL_COLOR_ATTACHMENT0, image, 0);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target_.get());
  glViewport(0, 0, width_px, height_px);
  glDisable(GL_FRAMEBUFFER_SRGB);
  glDisable(GL_BLEND);
  glDisable(GL_SCISSOR_TEST);
  glUseProgram(program_.get());
  glUniform1i(left_px_location_, left_px);
  glUniform1i(to_linear_location_, to_linear ? 1 : 0);
  glBindVertexArray(vertex_array_.get());
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, frame_.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glNamedFramebufferTexture(target_.get(), GL_COLOR_ATTACHMENT0, 0, 0);
  gl::check_gl_error("OpenXR: copying an eye's half into its swapchain image");
}

ImageRGBA OpenXrViewCopier::read_view(GLuint image, int width_px, int height_px, bool from_linear) {
  const SavedGlState saved;
  // Read through a framebuffer with sRGB writes off: glReadPixels returns the stored values of an
  // sRGB image as they are (no decode), the drive values the copy wrote.
  const gl::Framebuffer source = gl::create_framebuffer();
  glNamedFramebufferTexture(source.get(), GL_COLOR_ATTACHMENT0, image, 0);
  glNamedFramebufferReadBuffer(source.get(), GL_COLOR_ATTACHMENT0);
  glDisable(GL_FRAMEBUFFER_SRGB);
  ImageRGBA bottom_up(width_px, height_px);
  gl::read_back_framebuffer_rgba(source.get(), 0, 0, width_px, height_px, bottom_up.rgba.data(), gl::ReadBackKind::frame);
  gl::check_gl_error("OpenXR: reading a swapchain image back");
  ImageRGBA view(width_px, height_px);
  for (int y = 0; y < height_px; ++y)
    for (int x = 0; x < width_px; ++x) {
      const float* in = bottom_up.pixel(x, height_px - 1 - y);
      float* out = view.pixel(x, y);
      for (int c = 0; c < 3; ++c) out[c] = from_linear ? srgb_encode(in[c]) : in[c];
      out[3] = in[3];
    }
  return view;
}

}  // namespace glarelab

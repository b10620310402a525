#include "stimuli/frame_renderer.h"

#include <algorithm>

#include "core/errors.h"
#include "core/gl/shader_program.h"

namespace glarelab {
namespace {

ImageRGBA read_framebuffer(GLuint framebuffer, int width_px, int height_px) {
  ImageRGBA image(width_px, height_px);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  std::vector<float> bottom_up(image.rgba.size());
  glReadPixels(0, 0, width_px, height_px, GL_RGBA, GL_FLOAT, bottom_up.data());
  gl::check_gl_error("reading back a frame");
  // GL rows start at the bottom; glarelab images start at the top.
  const std::size_t row_floats = static_cast<std::size_t>(width_px) * 4;
  for (int y = 0; y < height_px; ++y) {
    std::copy_n(bottom_up.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(height_px - 1 - y) * row_floats),
                row_floats, image.rgba.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * row_floats));
  }
  return image;
}

}  // namespace

FrameRenderer::FrameRenderer(int width_px, int height_px)
    : width_px_(width_px),
      height_px_(height_px),
      stimulus_texture_(gl::create_texture(GL_TEXTURE_2D)),
      stimulus_framebuffer_(gl::create_framebuffer()),
      empty_vertex_array_(gl::create_vertex_array()),
      placed_image_program_(gl::build_program({"stimuli/shaders/placed_image.vert", "stimuli/shaders/placed_image.frag"})),
      encode_program_(gl::build_program({"stimuli/shaders/fullscreen.vert", "stimuli/shaders/encode_display.frag"})) {
  // 32-bit float: a 1e8 cd/m2 source and a 1e-2 cd/m2 background must both survive exactly.
  glTextureStorage2D(stimulus_texture_.get(), 1, GL_RGBA32F, width_px_, height_px_);
  glTextureParameteri(stimulus_texture_.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(stimulus_texture_.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glNamedFramebufferTexture(stimulus_framebuffer_.get(), GL_COLOR_ATTACHMENT0, stimulus_texture_.get(), 0);
  const GLenum status = glCheckNamedFramebufferStatus(stimulus_framebuffer_.get(), GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw DisplayError("OpenGL: the RGBA32F stimulus framebuffer is incomplete (status " + std::to_string(status) + ")");
  gl::check_gl_error("creating the stimulus framebuffer");
}

SceneTexture FrameRenderer::upload(const ImageRGBA& image) const {
  SceneTexture scene{gl::create_texture(GL_TEXTURE_2D), image.width_px, image.height_px};
  glTextureStorage2D(scene.texture.get(), 1, GL_RGBA32F, image.width_px, image.height_px);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(scene.texture.get(), 0, 0, 0, image.width_px, image.height_px, GL_RGBA, GL_FLOAT,
                      image.rgba.data());
  glTextureParameteri(scene.texture.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(scene.texture.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  gl::check_gl_error("uploading a scene image");
  return scene;
}

void FrameRenderer::compose(const std::vector<Placement>& placements, double background_cd_m2) {
  glBindFramebuffer(GL_FRAMEBUFFER, stimulus_framebuffer_.get());
  glViewport(0, 0, width_px_, height_px_);
  glDisable(GL_BLEND);
  glDisable(GL_DEPTH_TEST);
  const auto background = static_cast<float>(background_cd_m2);
  const float clear_colour[4] = {background, background, background, 1.0f};
  glClearNamedFramebufferfv(stimulus_framebuffer_.get(), GL_COLOR, 0, clear_colour);

  draw_placements(placements, false);
  gl::check_gl_error("composing a stimulus frame");
}

void FrameRenderer::compose_overlay(const std::vector<Placement>& overlays) {
  glBindFramebuffer(GL_FRAMEBUFFER, stimulus_framebuffer_.get());
  glViewport(0, 0, width_px_, height_px_);
  glDisable(GL_DEPTH_TEST);
  // Premultiplied "over": frame = overlay + (1 - coverage) frame; the frame's alpha stays 1.
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
  draw_placements(overlays, true);
  glDisable(GL_BLEND);
  gl::check_gl_error("drawing an overlay on a stimulus frame");
}

void FrameRenderer::draw_placements(const std::vector<Placement>& placements, bool overlay) {
  glUseProgram(placed_image_program_.get());
  glBindVertexArray(empty_vertex_array_.get());
  glUniform2f(glGetUniformLocation(placed_image_program_.get(), "uViewportPx"), static_cast<float>(width_px_),
              static_cast<float>(height_px_));
  glUniform1i(glGetUniformLocation(placed_image_program_.get(), "uOverlay"), overlay ? 1 : 0);
  glEnable(GL_SCISSOR_TEST);
  for (const Placement& placement : placements) {
    // Scissor rectangles are bottom-up in GL.
    glScissor(placement.clip.x_px, height_px_ - placement.clip.y_px - placement.clip.height_px, placement.clip.width_px,
              placement.clip.height_px);
    glUniform4f(glGetUniformLocation(placed_image_program_.get(), "uRectPx"), static_cast<float>(placement.rect.x_px),
                static_cast<float>(placement.rect.y_px), static_cast<float>(placement.rect.width_px),
                static_cast<float>(placement.rect.height_px));
    glUniform1f(glGetUniformLocation(placed_image_program_.get(), "uScale"), static_cast<float>(placement.scale_cd_m2));
    glBindTextureUnit(0, placement.scene->texture.get());
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
  }
  glDisable(GL_SCISSOR_TEST);
}

void FrameRenderer::encode_to_display(const DisplaySpec& display) {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, width_px_, height_px_);
  glUseProgram(encode_program_.get());
  glBindVertexArray(empty_vertex_array_.get());
  glUniform1f(glGetUniformLocation(encode_program_.get(), "uPeakLuminance"),
              static_cast<float>(display.peak_luminance_cd_m2));
  glUniform1i(glGetUniformLocation(encode_program_.get(), "uEncoding"),
              display.encoding == DisplayEncoding::srgb ? 0 : 1);
  glUniform1f(glGetUniformLocation(encode_program_.get(), "uGamma"), static_cast<float>(display.gamma));
  glBindTextureUnit(0, stimulus_texture_.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  gl::check_gl_error("encoding a frame for the display");
}

ImageRGBA FrameRenderer::read_stimulus() const {
  return read_framebuffer(stimulus_framebuffer_.get(), width_px_, height_px_);
}

void FrameRenderer::replace_stimulus(const ImageRGBA& image) {
  if (image.width_px != width_px_ || image.height_px != height_px_)
    throw DisplayError("frame renderer: replacing the " + std::to_string(width_px_) + "x" + std::to_string(height_px_) +
                       " stimulus with a " + std::to_string(image.width_px) + "x" + std::to_string(image.height_px) +
                       " image");
  // GL rows start at the bottom; glarelab images start at the top.
  const std::size_t row_floats = static_cast<std::size_t>(width_px_) * 4;
  std::vector<float> bottom_up(image.rgba.size());
  for (int y = 0; y < height_px_; ++y) {
    std::copy_n(image.rgba.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * row_floats), row_floats,
                bottom_up.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(height_px_ - 1 - y) * row_floats));
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(stimulus_texture_.get(), 0, 0, 0, width_px_, height_px_, GL_RGBA, GL_FLOAT, bottom_up.data());
  gl::check_gl_error("replacing the stimulus frame");
}

void FrameRenderer::replace_stimulus_region(const ImageRGBA& region, int x0_px, int y0_px) {
  if (region.width_px == 0 || region.height_px == 0) return;
  if (x0_px < 0 || y0_px < 0 || x0_px + region.width_px > width_px_ || y0_px + region.height_px > height_px_)
    throw DisplayError("frame renderer: a " + std::to_string(region.width_px) + "x" + std::to_string(region.height_px) +
                       " region at (" + std::to_string(x0_px) + ", " + std::to_string(y0_px) + ") outside the " +
                       std::to_string(width_px_) + "x" + std::to_string(height_px_) + " stimulus");
  // GL rows start at the bottom; glarelab images start at the top.
  const std::size_t row_floats = static_cast<std::size_t>(region.width_px) * 4;
  std::vector<float> bottom_up(region.rgba.size());
  for (int y = 0; y < region.height_px; ++y)
    std::copy_n(region.rgba.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * row_floats), row_floats,
                bottom_up.begin() +
                    static_cast<std::ptrdiff_t>(static_cast<std::size_t>(region.height_px - 1 - y) * row_floats));
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(stimulus_texture_.get(), 0, x0_px, height_px_ - y0_px - region.height_px, region.width_px,
                      region.height_px, GL_RGBA, GL_FLOAT, bottom_up.data());
  gl::check_gl_error("replacing a region of the stimulus frame");
}

ImageRGBA FrameRenderer::read_display() const { return read_framebuffer(0, width_px_, height_px_); }

}  // namespace glarelab

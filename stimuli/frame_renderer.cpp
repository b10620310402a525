#include "stimuli/frame_renderer.h"

#include <algorithm>

#include "core/errors.h"
#include "core/gl/read_back.h"
#include "core/gl/shader_program.h"

namespace glarelab {
namespace {

ImageRGBA read_framebuffer(GLuint framebuffer, int width_px, int height_px) {
  ImageRGBA image(width_px, height_px);
  std::vector<float> bottom_up(image.rgba.size());
  gl::read_back_framebuffer_rgba(framebuffer, 0, 0, width_px, height_px, bottom_up.data(), gl::ReadBackKind::frame);
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
      placed_image_program_(gl::build_program({"stimuli/shaders/placed_image.vert", "stimuli/shaders/placed_image.frag"})) {
  encode_program(0, false);  // the common one built now, so a driver that cannot build it says so at once
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

void FrameRenderer::mark_unencoded(const PixelRect& rect) {
  unencoded_ = bounding_rect(unencoded_, intersection(rect, PixelRect{0, 0, width_px_, height_px_}));
}

void FrameRenderer::compose(const std::vector<Placement>& placements, double background_cd_m2) {
  ++stimulus_generation_;
  mark_unencoded(PixelRect{0, 0, width_px_, height_px_});
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
  ++stimulus_generation_;
  // Each overlay draws its rectangle within its clip (draw_placements).
  for (const Placement& overlay : overlays) mark_unencoded(intersection(overlay.rect, overlay.clip));
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

void FrameRenderer::prepare_display_target(int bits_per_channel) {
  if (bits_per_channel == target_bits_) return;
  GLenum format = GL_RGBA8;
  if (bits_per_channel == 10) {
    format = GL_RGB10_A2;
  } else if (bits_per_channel == 16) {
    format = GL_RGBA16F;
  } else if (bits_per_channel != 8) {
    throw DisplayError("frame renderer: " + std::to_string(bits_per_channel) +
                       " bits per channel requested (supported: 8, 10, 16 half float)");
  }
  display_target_ = gl::create_texture(GL_TEXTURE_2D);
  glTextureStorage2D(display_target_.get(), 1, format, width_px_, height_px_);
  display_framebuffer_ = gl::create_framebuffer();
  glNamedFramebufferTexture(display_framebuffer_.get(), GL_COLOR_ATTACHMENT0, display_target_.get(), 0);
  const GLenum status = glCheckNamedFramebufferStatus(display_framebuffer_.get(), GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    target_bits_ = 0;
    throw DisplayError("OpenGL: the " + std::to_string(bits_per_channel) +
                       "-bit display framebuffer is incomplete (status " + std::to_string(status) + ")");
  }
  gl::check_gl_error("creating the display framebuffer");
  target_bits_ = bits_per_channel;
}

void FrameRenderer::prepare_calibration_table(const DisplayCalibration& calibration) {
  // Built on first use: most sessions never encode through a table.
  if (!encode_table_program_)
    encode_table_program_ =
        gl::build_program({"stimuli/shaders/fullscreen.vert", "stimuli/shaders/encode_display_table.frag"});
  if (calibration_texture_.get() != 0 && calibration.drive == uploaded_calibration_.drive &&
      calibration.luminance_cd_m2 == uploaded_calibration_.luminance_cd_m2)
    return;
  GLint max_size = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
  const auto rows = static_cast<GLsizei>(calibration.rows());
  if (rows < 2 || rows > max_size)
    throw DisplayError("frame renderer: a calibration table of " + std::to_string(rows) + " rows (2 to " +
                       std::to_string(max_size) + " fit a texture)");
  std::vector<float> texels;
  texels.reserve(static_cast<std::size_t>(rows) * 4);
  for (std::size_t i = 0; i < calibration.rows(); ++i) {
    texels.push_back(static_cast<float>(calibration.drive[i]));
    for (const std::vector<double>& channel : calibration.luminance_cd_m2)
      texels.push_back(static_cast<float>(channel[i] - channel.front()));
  }
  // The table read forward at each 8-bit code: the two gains the dither chooses between.
  std::vector<float> code_gains;
  constexpr int kDitherLevels = 255;
  for (int code = 0; code <= kDitherLevels; ++code) {
    code_gains.push_back(static_cast<float>(code) / kDitherLevels);
    for (int c = 0; c < 3; ++c)
      code_gains.push_back(static_cast<float>(calibration.channel_gain_cd_m2(c, code / static_cast<double>(kDitherLevels))));
  }
  const auto upload_row = [](gl::Texture& texture, GLsizei width, const std::vector<float>& data) {
    texture = gl::create_texture(GL_TEXTURE_2D);
    glTextureStorage2D(texture.get(), 1, GL_RGBA32F, width, 1);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(texture.get(), 0, 0, 0, width, 1, GL_RGBA, GL_FLOAT, data.data());
    glTextureParameteri(texture.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(texture.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  };
  upload_row(calibration_texture_, rows, texels);
  upload_row(code_gain_texture_, kDitherLevels + 1, code_gains);
  gl::check_gl_error("uploading the display calibration table");
  uploaded_calibration_ = calibration;
}

void FrameRenderer::encode_to_display(const DisplaySpec& display) { encode_rect(display, PixelRect{0, 0, width_px_, height_px_}); }

void FrameRenderer::encode_changes_to_display(const DisplaySpec& display) {
  if (!encoded_once_) {
    encode_to_display(display);
    return;
  }
  if (unencoded_.empty()) return;
  encode_rect(display, unencoded_);
}

void FrameRenderer::encode_rect(const DisplaySpec& display, const PixelRect& rect) {
  const bool quantise = display.bits_per_channel != 0;
  // GL's scissor and blit rectangles start at the bottom row.
  const int gl_y0 = height_px_ - rect.y_px - rect.height_px;
  const bool whole = rect.x_px == 0 && rect.y_px == 0 && rect.width_px == width_px_ && rect.height_px == height_px_;
  if (quantise) prepare_display_target(display.bits_per_channel);
  const bool table = display.encoding == DisplayEncoding::table;
  if (table) prepare_calibration_table(display.calibration);
  const GLuint target = quantise ? display_framebuffer_.get() : display_output_;
  glBindFramebuffer(GL_FRAMEBUFFER, target);
  glViewport(0, 0, width_px_, height_px_);
  glDisable(GL_BLEND);
  // The pass writes the drive values themselves (its own ordered dither at 8 bits, none deeper);
  // GL_DITHER, on by default, would let a driver dither them again into the target, so that a
  // uniform field (the straylight test field's halves) no longer held one code.
  glDisable(GL_DITHER);
  if (whole) {
    glDisable(GL_SCISSOR_TEST);
  } else {
    glEnable(GL_SCISSOR_TEST);
    glScissor(rect.x_px, gl_y0, rect.width_px, rect.height_px);
  }
  // Only an 8-bit target is dithered: 10 bits and half float already hold steps below what an
  // observer resolves at the luminances of interest (docs/DISPLAY_CALIBRATION.md).
  const int dither_levels = display.bits_per_channel == 8 ? 255 : 0;
  int encoding = 0;
  if (display.encoding == DisplayEncoding::gamma) encoding = 1;
  if (display.encoding == DisplayEncoding::pq) encoding = 2;
  const GLuint program = table ? encode_table_program_.get() : encode_program(encoding, dither_levels > 0);
  glUseProgram(program);
  glBindVertexArray(empty_vertex_array_.get());
  glUniform1i(glGetUniformLocation(program, "uDitherLevels"), dither_levels);
  if (table) {
    const DisplayCalibration& calibration = display.calibration;
    glUniform1f(glGetUniformLocation(program, "uPeakLuminance"), static_cast<float>(calibration.peak_cd_m2()));
    glUniform1f(glGetUniformLocation(program, "uBlack"), static_cast<float>(calibration.black_cd_m2()));
    glUniform1i(glGetUniformLocation(program, "uTableRows"), static_cast<GLint>(calibration.rows()));
    glBindTextureUnit(1, calibration_texture_.get());
    glBindTextureUnit(2, code_gain_texture_.get());
  } else {
    glUniform1f(glGetUniformLocation(program, "uPeakLuminance"), static_cast<float>(display.peak_luminance_cd_m2));
    glUniform1f(glGetUniformLocation(program, "uGamma"), static_cast<float>(display.gamma));
    glUniform1i(glGetUniformLocation(program, "uBt2020"), display.primaries == DisplayPrimaries::bt2020 ? 1 : 0);
  }
  glBindTextureUnit(0, stimulus_texture_.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  if (table) {
    glBindTextureUnit(1, 0);
    glBindTextureUnit(2, 0);
  }
  if (quantise) {
    // The default framebuffer gets the quantised frame (a window's is requested at this depth).
    glDisable(GL_SCISSOR_TEST);  // the blit takes its rectangle, not the scissor
    glBlitNamedFramebuffer(target, display_output_, rect.x_px, gl_y0, rect.x_px + rect.width_px, gl_y0 + rect.height_px, rect.x_px, gl_y0,
                           rect.x_px + rect.width_px, gl_y0 + rect.height_px, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, display_output_);
  }
  glDisable(GL_SCISSOR_TEST);
  read_from_target_ = quantise;
  unencoded_ = PixelRect{};
  encoded_once_ = true;
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
  ++stimulus_generation_;
  mark_unencoded(PixelRect{0, 0, width_px_, height_px_});
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
  // GL rows start at the bottom; glarelab images start at the top.
  const std::size_t row_floats = static_cast<std::size_t>(region.width_px) * 4;
  std::vector<float> bottom_up(region.rgba.size());
  for (int y = 0; y < region.height_px; ++y)
    std::copy_n(region.rgba.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * row_floats), row_floats,
                bottom_up.begin() +
                    static_cast<std::ptrdiff_t>(static_cast<std::size_t>(region.height_px - 1 - y) * row_floats));
  replace_stimulus_region_bottom_up(bottom_up, x0_px, y0_px, region.width_px, region.height_px);
}

void FrameRenderer::replace_stimulus_region_bottom_up(const std::vector<float>& rgba_bottom_up, int x0_px, int y0_px,
                                                      int width_px, int height_px) {
  upload_stimulus_region(rgba_bottom_up.data(), rgba_bottom_up.size(), 4, GL_FLOAT, x0_px, y0_px, width_px, height_px,
                         "replacing a region of the stimulus frame");
}

void FrameRenderer::replace_stimulus_region_half_rgb(const std::vector<std::uint16_t>& rgb_bottom_up, int x0_px,
                                                     int y0_px, int width_px, int height_px) {
  // GL_RGB into the RGBA32F stimulus sets alpha to 1.
  upload_stimulus_region(rgb_bottom_up.data(), rgb_bottom_up.size(), 3, GL_HALF_FLOAT, x0_px, y0_px, width_px,
                         height_px, "replacing a region of the stimulus frame from half floats");
}

void FrameRenderer::replace_stimulus_region_half_rgb_part(const std::vector<std::uint16_t>& rgb_bottom_up, int x0_px,
                                                          int y0_px, int width_px, int height_px,
                                                          const PixelRect& part) {
  if (part.empty()) return;  // nothing differs: nothing written, wherever its corner lies
  if (!PixelRect{x0_px, y0_px, width_px, height_px}.contains(part))
    throw DisplayError("frame renderer: a " + std::to_string(part.width_px) + "x" + std::to_string(part.height_px) +
                       " part at (" + std::to_string(part.x_px) + ", " + std::to_string(part.y_px) + ") outside its " +
                       std::to_string(width_px) + "x" + std::to_string(height_px) + " region at (" +
                       std::to_string(x0_px) + ", " + std::to_string(y0_px) + ")");
  upload_stimulus_region(rgb_bottom_up.data(), rgb_bottom_up.size(), 3, GL_HALF_FLOAT, x0_px, y0_px, width_px,
                         height_px, "replacing part of a region of the stimulus frame from half floats", &part);
}

void FrameRenderer::upload_stimulus_region(const void* values, std::size_t count, int channels, unsigned type,
                                           int x0_px, int y0_px, int width_px, int height_px, const char* what,
                                           const PixelRect* part) {
  if (width_px == 0 || height_px == 0) return;
  if (x0_px < 0 || y0_px < 0 || width_px < 0 || height_px < 0 || x0_px + width_px > width_px_ ||
      y0_px + height_px > height_px_)
    throw DisplayError("frame renderer: a " + std::to_string(width_px) + "x" + std::to_string(height_px) +
                       " region at (" + std::to_string(x0_px) + ", " + std::to_string(y0_px) + ") outside the " +
                       std::to_string(width_px_) + "x" + std::to_string(height_px_) + " stimulus");
  if (count != static_cast<std::size_t>(channels) * static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px))
    throw DisplayError("frame renderer: " + std::to_string(count) + " values for a " + std::to_string(width_px) + "x" +
                       std::to_string(height_px) + " region of " + std::to_string(channels) + " channels");
  ++stimulus_generation_;
  const PixelRect written = part != nullptr ? *part : PixelRect{x0_px, y0_px, width_px, height_px};
  mark_unencoded(written);
  // Rows of half RGB (6 bytes a pixel) are only 2-byte aligned.
  glPixelStorei(GL_UNPACK_ALIGNMENT, type == GL_HALF_FLOAT ? 2 : 4);
  if (part != nullptr) {
    // The part's rows read where they lie in the region's (bottom-up): GL skips the columns left of
    // it and the region's rows below it, and steps by the region's width.
    glPixelStorei(GL_UNPACK_ROW_LENGTH, width_px);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, part->x_px - x0_px);
    glPixelStorei(GL_UNPACK_SKIP_ROWS, y0_px + height_px - part->bottom_px());
  }
  glTextureSubImage2D(stimulus_texture_.get(), 0, written.x_px, height_px_ - written.bottom_px(), written.width_px,
                      written.height_px, channels == 3 ? GL_RGB : GL_RGBA, type, values);
  if (part != nullptr) {
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
    glPixelStorei(GL_UNPACK_SKIP_ROWS, 0);
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  gl::check_gl_error(what);
}

void FrameRenderer::replace_stimulus_region_from_buffer(unsigned buffer, int x0_px, int y0_px, int width_px,
                                                        int height_px) {
  if (width_px == 0 || height_px == 0) return;
  if (x0_px < 0 || y0_px < 0 || width_px < 0 || height_px < 0 || x0_px + width_px > width_px_ ||
      y0_px + height_px > height_px_)
    throw DisplayError("frame renderer: a " + std::to_string(width_px) + "x" + std::to_string(height_px) +
                       " frame on the GPU at (" + std::to_string(x0_px) + ", " + std::to_string(y0_px) +
                       ") outside the " + std::to_string(width_px_) + "x" + std::to_string(height_px_) + " stimulus");
  if (!from_buffer_program_) from_buffer_program_ = gl::build_program({"stimuli/shaders/stimulus_from_buffer.comp"});
  ++stimulus_generation_;
  mark_unencoded(PixelRect{x0_px, y0_px, width_px, height_px});
  const GLuint program = from_buffer_program_.get();
  glUseProgram(program);
  glUniform2i(glGetUniformLocation(program, "uOrigin"), x0_px, y0_px);
  glUniform2i(glGetUniformLocation(program, "uSize"), width_px, height_px);
  glUniform1i(glGetUniformLocation(program, "uStimulusHeight"), height_px_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffer);
  glBindImageTexture(0, stimulus_texture_.get(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  constexpr GLuint kTile = 16;  // the shader's local size
  glDispatchCompute((static_cast<GLuint>(width_px) + kTile - 1) / kTile, (static_cast<GLuint>(height_px) + kTile - 1) / kTile,
                    1);
  // The encode samples the texture and a read-back or blend reads the framebuffer next.
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                  GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
  glUseProgram(0);
  gl::check_gl_error("drawing a frame from the GPU into the stimulus frame");
}

void FrameRenderer::finish() const { glFinish(); }

GLuint FrameRenderer::encode_program(int encoding, bool dither) {
  const int key = 2 * encoding + (dither ? 1 : 0);
  auto found = encode_programs_.find(key);
  if (found == encode_programs_.end()) {
    const std::string defines =
        "#define ENCODING " + std::to_string(encoding) + "\n#define DITHER " + std::string(dither ? "1" : "0");
    found = encode_programs_
                .emplace(key, gl::build_program({"stimuli/shaders/fullscreen.vert", "stimuli/shaders/encode_display.frag"},
                                                defines))
                .first;
  }
  return found->second.get();
}

ImageRGBA FrameRenderer::read_display() const {
  return read_framebuffer(read_from_target_ ? display_framebuffer_.get() : display_output_, width_px_, height_px_);
}

}  // namespace glarelab

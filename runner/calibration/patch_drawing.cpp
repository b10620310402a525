#include "runner/calibration/patch_drawing.h"

#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/gl/read_back.h"
#include "core/gl/shader_program.h"

namespace glarelab {

void draw_calibration_patch(int width_px, int height_px, double patch_fraction, const std::array<double, 3>& rgb_drive,
                            unsigned framebuffer) {
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
  // Nothing may change the cleared values on their way to the framebuffer: GL_DITHER is on by
  // default, and an sRGB-capable framebuffer would encode them again.
  glDisable(GL_DITHER);
  glDisable(GL_FRAMEBUFFER_SRGB);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDisable(GL_SCISSOR_TEST);
  glViewport(0, 0, width_px, height_px);
  const bool full_screen = patch_fraction >= 1.0;
  if (!full_screen) {
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    const int patch_width = std::max(1, static_cast<int>(std::lround(patch_fraction * width_px)));
    const int patch_height = std::max(1, static_cast<int>(std::lround(patch_fraction * height_px)));
    glEnable(GL_SCISSOR_TEST);
    glScissor((width_px - patch_width) / 2, (height_px - patch_height) / 2, patch_width, patch_height);
  }
  glClearColor(static_cast<float>(rgb_drive[0]), static_cast<float>(rgb_drive[1]), static_cast<float>(rgb_drive[2]),
               1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);
  gl::check_gl_error("calibrate: drawing a patch");
}

ImageRGBA read_default_framebuffer(int width_px, int height_px, unsigned framebuffer) {
  ImageRGBA image(width_px, height_px);
  std::vector<float> bottom_up(image.rgba.size());
  gl::read_back_framebuffer_rgba(framebuffer, 0, 0, width_px, height_px, bottom_up.data(), gl::ReadBackKind::frame);
  gl::check_gl_error("calibrate: reading a patch back");
  // GL rows start at the bottom; glarelab images start at the top.
  const std::size_t row_floats = static_cast<std::size_t>(width_px) * 4;
  for (int y = 0; y < height_px; ++y)
    std::copy_n(bottom_up.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(height_px - 1 - y) * row_floats),
                row_floats, image.rgba.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * row_floats));
  return image;
}

}  // namespace glarelab

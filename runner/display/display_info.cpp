#include "runner/display/display_info.h"

#include <glad/gl.h>

#include <sstream>

namespace glarelab {
namespace {

// "8/8/8 bits", "16/16/16 float bits": the default framebuffer's colour buffer. A double-buffered
// default framebuffer is asked about its back buffer, a single-buffered one (OSMesa) its front.
std::string framebuffer_depth() {
  while (glGetError() != GL_NO_ERROR) {
  }
  for (const GLenum buffer : {GL_BACK_LEFT, GL_FRONT_LEFT}) {
    GLint bits[3] = {0, 0, 0};
    GLint component_type = GL_NONE;
    const GLenum channels[3] = {GL_FRAMEBUFFER_ATTACHMENT_RED_SIZE, GL_FRAMEBUFFER_ATTACHMENT_GREEN_SIZE,
                                GL_FRAMEBUFFER_ATTACHMENT_BLUE_SIZE};
    for (int c = 0; c < 3; ++c) glGetNamedFramebufferAttachmentParameteriv(0, buffer, channels[c], &bits[c]);
    glGetNamedFramebufferAttachmentParameteriv(0, buffer, GL_FRAMEBUFFER_ATTACHMENT_COMPONENT_TYPE, &component_type);
    if (glGetError() != GL_NO_ERROR || bits[0] == 0) continue;
    std::ostringstream depth;
    depth << bits[0] << "/" << bits[1] << "/" << bits[2] << (component_type == GL_FLOAT ? " float" : "") << " bits";
    return depth.str();
  }
  return "unknown (the driver did not say)";
}

}  // namespace

std::string describe_display_info(const DisplayBackend& display, const SessionClock& clock) {
  const GlInfo& gl = display.gl_info();
  std::ostringstream text;
  text << "backend " << display.kind() << " " << display.width_px() << "x" << display.height_px() << "; mode "
       << display.display_mode() << "; refresh " << display.refresh_hz() << " Hz"
       << (display.real_time() ? "" : " (virtual)") << "; framebuffer " << framebuffer_depth()
       << "; GL renderer " << gl.renderer << "; GL vendor " << gl.vendor << "; GL version (driver) " << gl.version
       << "; GLSL " << gl.shading_language_version << "; context " << (gl.platform.empty() ? "-" : gl.platform)
       << "; clock " << clock.name();
  return text.str();
}

}  // namespace glarelab

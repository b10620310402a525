#include "core/gl/gl_context.h"

namespace glarelab {

std::string GlInfo::describe() const {
  return "OpenGL " + version + " on " + renderer + " (" + vendor + ")" + (platform.empty() ? "" : " via " + platform);
}

}  // namespace glarelab

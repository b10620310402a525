#include "runner/display/gl_driver_pin.h"

#include <string>

#include "runner/display/module_pin.h"

namespace glarelab {
namespace {

bool is_gl_driver(const std::string& path) {
  const std::string file = path.substr(path.find_last_of('/') + 1);
  if (path.find("/dri/") != std::string::npos) return true;
  for (const char* prefix : {"libGLX", "libGL.", "libGLdispatch", "libEGL", "libglapi", "libgbm", "libgallium"})
    if (file.rfind(prefix, 0) == 0) return true;
  return false;
}

}  // namespace

void keep_gl_driver_loaded() { keep_modules_loaded(is_gl_driver); }

}  // namespace glarelab

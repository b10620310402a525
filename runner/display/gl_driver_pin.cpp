#include "runner/display/gl_driver_pin.h"

#include <dlfcn.h>
#include <link.h>

#include <string>

namespace glarelab {
namespace {

bool is_gl_driver(const std::string& path) {
  const std::string file = path.substr(path.find_last_of('/') + 1);
  if (path.find("/dri/") != std::string::npos) return true;
  for (const char* prefix : {"libGLX", "libGL.", "libGLdispatch", "libEGL", "libglapi", "libgbm", "libgallium"})
    if (file.rfind(prefix, 0) == 0) return true;
  return false;
}

int pin_gl_module(struct dl_phdr_info* info, std::size_t, void*) {
  const std::string path = info->dlpi_name != nullptr ? info->dlpi_name : "";
  if (!path.empty() && is_gl_driver(path)) dlopen(path.c_str(), RTLD_LAZY | RTLD_NOLOAD | RTLD_NODELETE);  // never closed
  return 0;
}

}  // namespace

void keep_gl_driver_loaded() { dl_iterate_phdr(pin_gl_module, nullptr); }

}  // namespace glarelab

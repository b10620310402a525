// The one place a display backend is chosen. Adding EGL headless means one more branch here and
// one more sibling file; callers only see DisplayBackend.
#include "runner/display/display_backend.h"
#include "runner/display/glfw_display.h"
#include "runner/display/osmesa_display.h"

namespace glarelab {

std::vector<std::string> display_kinds() { return {"window", "offscreen"}; }

std::unique_ptr<DisplayBackend> create_display(const std::string& kind, const DisplayRequest& request) {
  if (kind == "window") return create_glfw_display(request);
  if (kind == "offscreen") return create_osmesa_display(request);
  throw DisplayError("display: unknown backend '" + kind + "' (choose window or offscreen)");
}

}  // namespace glarelab

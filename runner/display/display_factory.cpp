// The one place a display backend is chosen. "offscreen" takes EGL (a GPU on a headless server,
// or llvmpipe) and falls back to OSMesa, keeping EGL's answer in the context's platform text;
// "openxr" a head-mounted display through an OpenXR runtime (openxr_display.h);
// "egl" and "osmesa" ask for one of them and fail (DisplayError, exit 3) when it cannot start.
#include "runner/display/display_backend.h"
#include "runner/display/egl_display.h"
#include "runner/display/glfw_display.h"
#include "runner/display/openxr_display.h"
#include "runner/display/osmesa_display.h"

namespace glarelab {

std::vector<std::string> display_kinds() { return {"window", "openxr", "offscreen", "egl", "osmesa"}; }

std::unique_ptr<DisplayBackend> create_display(const std::string& kind, const DisplayRequest& request) {
  if (kind == "window") return create_glfw_display(request);
  if (kind == "openxr") return create_openxr_display(request);
  if (kind == "egl") return create_egl_display(request);
  if (kind == "osmesa") return create_osmesa_display(request);
  if (kind == "offscreen") {
    std::string why_not_egl;
    try {
      return create_egl_display(request);
    } catch (const DisplayError& egl_failure) {
      why_not_egl = egl_failure.what();
    }
    try {
      return create_osmesa_display(request, why_not_egl);
    } catch (const DisplayError& osmesa_failure) {
      throw DisplayError(std::string(osmesa_failure.what()) + " (tried first: " + why_not_egl + ")");
    }
  }
  throw DisplayError("display: unknown backend '" + kind + "' (choose window, openxr, offscreen, egl or osmesa)");
}

}  // namespace glarelab

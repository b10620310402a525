#include "runner/display/headless_display.h"

#include <glad/gl.h>

namespace glarelab {

HeadlessDisplay::HeadlessDisplay(const DisplayRequest& request, const std::string& subsystem)
    : width_px_(request.width_px), height_px_(request.height_px), refresh_hz_(request.refresh_hz) {
  if (width_px_ < 1 || height_px_ < 1) throw DisplayError(subsystem + ": framebuffer size must be at least 1x1");
}

void HeadlessDisplay::present() { glFinish(); }

}  // namespace glarelab

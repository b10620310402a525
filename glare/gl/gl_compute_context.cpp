#include "glare/gl/gl_compute_context.h"

namespace glarelab::gl {

std::unique_ptr<DisplayBackend> create_compute_context() {
  DisplayRequest request;
  request.width_px = 16;
  request.height_px = 16;
  request.visible = false;
  request.vsync = false;
  request.title = "glarelab compute";
  return create_display("offscreen", request);
}

}  // namespace glarelab::gl

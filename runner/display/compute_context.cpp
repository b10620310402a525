#include "runner/display/compute_context.h"

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

GlContextFactory display_context_factory(DisplayBackend& display) { return one_context_factory(display); }

GlContextFactory compute_context_factory() {
  return []() -> std::unique_ptr<GlContext> { return create_compute_context(); };
}

}  // namespace glarelab::gl

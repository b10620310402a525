#pragma once
// Window display: GLFW, OpenGL 4.5 core, chosen monitor, fullscreen or windowed, vsync on.
// Frames reach a real display and are timed on the monotonic session clock.
#include <memory>

#include "runner/display/display_backend.h"

namespace glarelab {
std::unique_ptr<DisplayBackend> create_glfw_display(const DisplayRequest& request);
}  // namespace glarelab

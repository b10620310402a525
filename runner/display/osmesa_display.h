#pragma once
// Offscreen display: an OSMesa OpenGL 4.5 core context (llvmpipe) rendering into a float RGBA
// buffer in memory. Needs no display server; frames are timed by the virtual clock.
#include <memory>

#include "runner/display/display_backend.h"

namespace glarelab {
std::unique_ptr<DisplayBackend> create_osmesa_display(const DisplayRequest& request);
}  // namespace glarelab

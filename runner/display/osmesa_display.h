#pragma once
// Offscreen display: an OSMesa OpenGL 4.5 core context (llvmpipe) rendering into a float RGBA
// buffer in memory. Needs no display server; frames are timed by the virtual clock.
#include <memory>
#include <string>

#include "runner/display/display_backend.h"

namespace glarelab {
// `why_not_egl`: when --display offscreen fell back to OSMesa, what EGL answered (kept in the
// context's platform text, so the session log says which offscreen path ran and why).
std::unique_ptr<DisplayBackend> create_osmesa_display(const DisplayRequest& request, const std::string& why_not_egl = {});
}  // namespace glarelab

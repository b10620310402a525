#pragma once
// The display's info dump, logged as the `display` event of every session (`glarelab run`) and of
// every timing test (`glarelab timing-test`), the way Psychtoolbox prints its screen and driver
// facts at the start of every script: enough to tell afterwards on what a session was shown and
// what its timing can be compared with. One place writes it, so both carry the same facts.
#include <string>

#include "core/clock.h"
#include "runner/display/display_backend.h"

namespace glarelab {

// "backend window 1280x720; mode windowed 1280x720 on monitor 0 'screen': video mode 1280x1024 at
// 60 Hz, 8/8/8 bits, vsync on; refresh 60 Hz; framebuffer 8/8/8 bits; GL renderer
// llvmpipe (LLVM 15.0.6, 256 bits); GL vendor Mesa; GL version (driver) 4.5 (Core Profile) Mesa
// 22.3.6; GLSL 4.50; context GLFW window, 8/8/8 bits framebuffer; clock monotonic". The framebuffer
// depth is read from the default framebuffer, so the display's context must be current (as it is
// right after create_display).
std::string describe_display_info(const DisplayBackend& display, const SessionClock& clock);

}  // namespace glarelab

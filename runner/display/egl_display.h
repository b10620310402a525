#pragma once
// Offscreen display through EGL (Khronos EGL 1.5, libEGL): an OpenGL 4.5 core context with a float
// pbuffer as its default framebuffer, and no display server. Unlike OSMesa (software only, and
// removed from Mesa 25.1) it reaches a GPU on a headless server: the EGL_EXT_platform_device
// platform picks the first hardware device (NVIDIA's driver and Mesa's both offer it); without one,
// Mesa's EGL_MESA_platform_surfaceless (a render node, or llvmpipe); then Mesa's software device.
// Frames are timed by the virtual clock, as OSMesa's are.
#include <memory>
#include <string>

#include "runner/display/display_backend.h"

namespace glarelab {

// Throws DisplayError "EGL: ..." naming each platform tried and what it answered.
std::unique_ptr<DisplayBackend> create_egl_display(const DisplayRequest& request);

}  // namespace glarelab

#pragma once
// A current OpenGL 4.5 core context for the glare engine's compute passes when no display is
// open: an offscreen (OSMesa) backend with a 16 x 16 default framebuffer, since every GL glare pass
// renders into its own buffers and textures. Throws DisplayError when no such context can be made.
#include <memory>

#include "runner/display/display_backend.h"

namespace glarelab::gl {

std::unique_ptr<DisplayBackend> create_compute_context();

}  // namespace glarelab::gl

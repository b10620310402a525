#pragma once
// A current OpenGL 4.5 core context for GL compute work when no display is open (the glare engine's
// GL path, its tests and benchmarks): an offscreen backend with a 16 x 16 default framebuffer, since
// every GL glare pass renders into its own buffers and textures. Throws DisplayError when no such
// context can be made. compute_context_factory() hands it to the layers below as a
// GlContextFactory (core/gl/gl_context.h).
#include <memory>

#include "runner/display/display_backend.h"

namespace glarelab::gl {

std::unique_ptr<DisplayBackend> create_compute_context();
GlContextFactory compute_context_factory();

}  // namespace glarelab::gl

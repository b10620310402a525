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

// The display's own context handed out as a GlContextFactory: each context it makes is a handle to
// `display`'s (made current by it, never destroying it), so that what GL work below runner/ makes
// there (the GL frame engine's frames) the display draws without a copy through the host. The
// display must outlive every handle.
GlContextFactory display_context_factory(DisplayBackend& display);

}  // namespace glarelab::gl

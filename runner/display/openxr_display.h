#pragma once
// Head-mounted display through OpenXR (`--display openxr`, `[display] output = "openxr"`;
// docs/STEREO.md). The session draws its side-by-side stereo frame, both eyes through the one
// per-eye frame path (runner/session/eye_glare.cpp), into the display's own float frame
// (frame_framebuffer(), RGBA32F); present() copies each half from it into its view's swapchain
// inside the runtime's frame loop (xrWaitFrame, xrBeginFrame, xrLocateViews, xrEndFrame with a
// projection layer) and then shows the frame in a mirror window (GLFW, GLX: the GL context, the
// keyboard and the experimenter's view). Flips are the runtime's predicted display times (predicted_display_time()).
// Built only where CMake found the OpenXR loader (libopenxr-dev); elsewhere creating it throws
// DisplayError naming OpenXR and why.
#include <memory>
#include <vector>

#include "core/image.h"
#include "runner/display/display_backend.h"

namespace glarelab {

// Throws DisplayError ("OpenXR: ...", exit 3) when the program was built without the loader, when
// no runtime answers (with the loader's own message), when the runtime offers no head-mounted
// display or no OpenGL on X11, or when its session does not become ready.
std::unique_ptr<DisplayBackend> create_openxr_display(const DisplayRequest& request);

// True when this build links the OpenXR loader.
bool openxr_built();

// Client-side readback of what the OpenXR display submitted: with keep on, every present() reads
// each view's swapchain image back (after the copy, before the image is released) and keeps it,
// frame by frame, until keep is set again. Each view is its image's drive values as the panel is
// to show them (a float image is encoded back with the sRGB curve it was decoded with), row 0 at
// the top, like the frame read from the default framebuffer. Process-wide, for checks of the
// backend (tests/openxr_*).
void keep_submitted_views(bool keep);
// The views of the last frame submitted while keeping; of every one, in order.
std::vector<ImageRGBA> last_submitted_views();
std::vector<std::vector<ImageRGBA>> submitted_views();

}  // namespace glarelab

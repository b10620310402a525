#pragma once
// The OpenGL driver a display loads (glvnd's libGLX/libEGL and their Mesa vendor libraries, Mesa's
// DRI or gallium driver, libglapi, libgbm) stays mapped until the process exits. GLFW, glvnd and
// EGL dlclose it at glfwTerminate or eglTerminate, while the driver's allocations are still
// referenced from its own globals: once the module is unmapped those allocations look
// unreachable, and LeakSanitizer reported them at exit as 128-240 bytes leaked from
// "<unknown module>" in every windowed and every EGL run (docs/HARDENING.md). Kept loaded,
// nothing leaks; the process frees it all at exit either way.
namespace glarelab {

// Marks every loaded OpenGL driver module RTLD_NODELETE (called once a context exists, when the
// driver is loaded).
void keep_gl_driver_loaded();

}  // namespace glarelab

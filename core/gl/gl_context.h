#pragma once
// An OpenGL context as every layer below runner/ sees it: what it is (GlInfo) and a way to make it
// current. The display backends of runner/display/ are such contexts; code that drives GL (the
// glare engine's GL path, the frame renderer) is handed one, or a factory that makes one, and so
// never reaches into the display backends (docs/ARCHITECTURE.md "Seams").
#include <functional>
#include <memory>
#include <string>

namespace glarelab {

struct GlInfo {
  std::string vendor;
  std::string renderer;
  std::string version;
  std::string shading_language_version;
  int major = 0;
  int minor = 0;
  // How the context was made: "EGL surfaceless, RGBA16F pbuffer", "OSMesa", "GLFW window", ...
  std::string platform;
  // "OpenGL 4.5 (Core Profile) Mesa 22.3.6 on llvmpipe (LLVM 15.0.6, 256 bits) (Mesa) via EGL surfaceless, ..."
  std::string describe() const;
};

class GlContext {
 public:
  virtual ~GlContext() = default;
  virtual const GlInfo& gl_info() const = 0;
  // Makes this context current on the calling thread and (re)loads GL entry points.
  virtual void make_current() = 0;
};

// Makes a new current OpenGL 4.5 core context, or throws DisplayError (core/errors.h) saying why
// none can be made. runner/display/compute_context.h has the one the program uses (offscreen).
using GlContextFactory = std::function<std::unique_ptr<GlContext>()>;

// A factory whose every context is a handle to `context` (made current by it, never destroying it):
// what GL work made in one of them is seen in all, so a frame one stage leaves in a GL buffer the
// next takes without a copy through the host. `context` must outlive every handle.
GlContextFactory one_context_factory(GlContext& context);

}  // namespace glarelab

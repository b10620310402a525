#include <glad/gl.h>

#include <algorithm>
#include <set>
#include <sstream>

#include "runner/display/display_backend.h"

namespace glarelab {

namespace {
std::string gl_string(GLenum name) {
  const auto* text = reinterpret_cast<const char*>(glGetString(name));
  return text ? std::string(text) : std::string("(none)");
}

thread_local const void* current_backend = nullptr;  // note_current_gl_backend's, per thread
}  // namespace

void note_current_gl_backend(const void* backend) { current_backend = backend; }
const void* current_gl_backend() { return current_backend; }

std::string describe_offered_context(GlProcLoader get_proc) {
  using GetString = const GLubyte*(GLAD_API_PTR*)(GLenum);
  auto get_string = reinterpret_cast<GetString>(get_proc("glGetString"));
  if (get_string == nullptr) return "";
  const auto* version = reinterpret_cast<const char*>(get_string(GL_VERSION));
  const auto* renderer = reinterpret_cast<const char*>(get_string(GL_RENDERER));
  return std::string("; the driver offers OpenGL ") + (version ? version : "?") + " on " + (renderer ? renderer : "?");
}

GlInfo load_and_check_gl(const char* subsystem, GlProcLoader get_proc, const DisplayRequest& request) {
  note_current_gl_backend(nullptr);  // the caller notes itself once the context is checked
  // glad's loader takes a function returning GLADapiproc; backends hand us void* getters.
  const int loaded = gladLoadGL(reinterpret_cast<GLADloadfunc>(get_proc));
  if (loaded == 0) {
    throw DisplayError(std::string(subsystem) + ": could not load OpenGL entry points (glGetString missing)");
  }
  GlInfo info;
  info.vendor = gl_string(GL_VENDOR);
  info.renderer = gl_string(GL_RENDERER);
  info.version = gl_string(GL_VERSION);
  info.shading_language_version = gl_string(GL_SHADING_LANGUAGE_VERSION);
  glGetIntegerv(GL_MAJOR_VERSION, &info.major);
  glGetIntegerv(GL_MINOR_VERSION, &info.minor);

  if (std::pair(info.major, info.minor) < std::pair(request.gl_major, request.gl_minor)) {
    std::ostringstream message;
    message << subsystem << ": OpenGL " << request.gl_major << "." << request.gl_minor
            << " core is required, but the context offers " << info.describe();
    throw DisplayError(message.str());
  }
  if (!request.required_extensions.empty()) {
    std::set<std::string> available;
    GLint count = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &count);
    for (GLint i = 0; i < count; ++i) {
      const auto* name = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i)));
      if (name) available.insert(name);
    }
    std::vector<std::string> missing;
    for (const auto& extension : request.required_extensions)
      if (!available.contains(extension)) missing.push_back(extension);
    if (!missing.empty()) {
      std::ostringstream message;
      message << subsystem << ": missing OpenGL extension(s)";
      for (const auto& name : missing) message << " " << name;
      message << " on " << info.describe() << " (" << count << " extensions available)";
      throw DisplayError(message.str());
    }
  }
  return info;
}

}  // namespace glarelab

#pragma once
// Builds GL programs from the embedded shader files (core/embedded_shaders.h). Compile and link
// errors throw DisplayError("OpenGL: <shader path>: <driver log>").
#include <initializer_list>
#include <string>
#include <string_view>

#include "core/gl/gl_objects.h"

namespace glarelab::gl {

// Paths relative to the source root, e.g. {"stimuli/shaders/fullscreen.vert", "stimuli/shaders/encode_display.frag"}.
// The stage is taken from the extension (.vert, .frag, .comp).
Program build_program(std::initializer_list<std::string_view> shader_paths);
// The same with `defines` ("#define NAME VALUE" lines) placed after each shader's #version line,
// for a program specialised at build time (a #line directive keeps the driver's line numbers).
Program build_program(std::initializer_list<std::string_view> shader_paths, std::string_view defines);

// The three texts glShaderSource receives for one shader, each with its length (GL then reads no
// terminator and nothing past them): with defines, the source's #version line, the defines and a
// #line directive back to the source's second line, and the rest of the source; without, the
// source whole and two empty texts. The views lie within `source`.
struct ShaderSourceTexts {
  std::string_view before_defines;
  std::string defines_block;
  std::string_view after_defines;
};
ShaderSourceTexts shader_source_texts(std::string_view source, std::string_view defines);

// Checks glGetError and throws DisplayError("OpenGL: <what>: <error name>") if one is pending.
void check_gl_error(std::string_view what);

}  // namespace glarelab::gl

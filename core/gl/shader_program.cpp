#include "core/gl/shader_program.h"

#include <string>
#include <vector>

#include "core/errors.h"
#include "core/embedded_shaders.h"

namespace glarelab::gl {
namespace {

GLenum stage_of(std::string_view path) {
  if (path.ends_with(".vert")) return GL_VERTEX_SHADER;
  if (path.ends_with(".frag")) return GL_FRAGMENT_SHADER;
  if (path.ends_with(".comp")) return GL_COMPUTE_SHADER;
  throw DisplayError("OpenGL: " + std::string(path) + ": unknown shader stage (expected .vert, .frag or .comp)");
}

std::string info_log(GLuint name, bool is_program) {
  GLint length = 0;
  if (is_program)
    glGetProgramiv(name, GL_INFO_LOG_LENGTH, &length);
  else
    glGetShaderiv(name, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(length > 0 ? length : 1), '\0');
  if (is_program)
    glGetProgramInfoLog(name, length, nullptr, log.data());
  else
    glGetShaderInfoLog(name, length, nullptr, log.data());
  while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
  return log;
}

}  // namespace

ShaderSourceTexts shader_source_texts(std::string_view source, std::string_view defines) {
  if (defines.empty()) return {source, std::string(), source.substr(source.size())};
  const std::size_t first_line_end = source.find('\n');
  if (first_line_end == std::string_view::npos)  // the #version line alone, with no line end
    return {source, "\n" + std::string(defines) + "\n#line 2\n", source.substr(source.size())};
  return {source.substr(0, first_line_end + 1), std::string(defines) + "\n#line 2\n", source.substr(first_line_end + 1)};
}

Program build_program(std::initializer_list<std::string_view> shader_paths) { return build_program(shader_paths, {}); }

Program build_program(std::initializer_list<std::string_view> shader_paths, std::string_view defines) {
  Program program(glCreateProgram());
  std::vector<Shader> shaders;
  std::string names;
  for (std::string_view path : shader_paths) {
    const std::string_view source = embedded_shader(path);
    if (source.empty()) throw DisplayError("OpenGL: shader " + std::string(path) + " is not embedded in this build");
    Shader shader(glCreateShader(stage_of(path)));
    const ShaderSourceTexts parts = shader_source_texts(source, defines);
    const char* texts[3] = {parts.before_defines.data(), parts.defines_block.data(), parts.after_defines.data()};
    const GLint lengths[3] = {static_cast<GLint>(parts.before_defines.size()), static_cast<GLint>(parts.defines_block.size()),
                              static_cast<GLint>(parts.after_defines.size())};
    glShaderSource(shader.get(), 3, texts, lengths);
    glCompileShader(shader.get());
    GLint ok = GL_FALSE;
    glGetShaderiv(shader.get(), GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) throw DisplayError("OpenGL: " + std::string(path) + ": " + info_log(shader.get(), false));
    glAttachShader(program.get(), shader.get());
    shaders.push_back(std::move(shader));
    names += (names.empty() ? "" : " + ") + std::string(path);
  }
  glLinkProgram(program.get());
  GLint linked = GL_FALSE;
  glGetProgramiv(program.get(), GL_LINK_STATUS, &linked);
  if (linked != GL_TRUE) throw DisplayError("OpenGL: linking " + names + ": " + info_log(program.get(), true));
  for (const auto& shader : shaders) glDetachShader(program.get(), shader.get());
  return program;
}

void check_gl_error(std::string_view what) {
  const GLenum error = glGetError();
  if (error == GL_NO_ERROR) return;
  std::string name;
  switch (error) {
    case GL_INVALID_ENUM: name = "GL_INVALID_ENUM"; break;
    case GL_INVALID_VALUE: name = "GL_INVALID_VALUE"; break;
    case GL_INVALID_OPERATION: name = "GL_INVALID_OPERATION"; break;
    case GL_OUT_OF_MEMORY: name = "GL_OUT_OF_MEMORY"; break;
    case GL_INVALID_FRAMEBUFFER_OPERATION: name = "GL_INVALID_FRAMEBUFFER_OPERATION"; break;
    default: name = "GL error " + std::to_string(error); break;
  }
  throw DisplayError("OpenGL: " + std::string(what) + ": " + name);
}

}  // namespace glarelab::gl

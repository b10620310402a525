#pragma once
// Move-only owners for OpenGL names: each deletes its name when it goes out of scope, so a GL
// object cannot outlive or leak past its owner. A current context is required to create and
// destroy them.
#include <glad/gl.h>

#include <utility>

namespace glarelab::gl {

template <void (*Delete)(GLuint)>
class Name {
 public:
  Name() = default;
  explicit Name(GLuint name) : name_(name) {}
  ~Name() { reset(); }
  Name(Name&& other) noexcept : name_(std::exchange(other.name_, 0)) {}
  Name& operator=(Name&& other) noexcept {
    if (this != &other) {
      reset();
      name_ = std::exchange(other.name_, 0);
    }
    return *this;
  }
  Name(const Name&) = delete;
  Name& operator=(const Name&) = delete;

  GLuint get() const { return name_; }
  explicit operator bool() const { return name_ != 0; }
  void reset() {
    if (name_ != 0) Delete(name_);
    name_ = 0;
  }

 private:
  GLuint name_ = 0;
};

namespace detail {
inline void delete_texture(GLuint name) { glDeleteTextures(1, &name); }
inline void delete_buffer(GLuint name) { glDeleteBuffers(1, &name); }
inline void delete_framebuffer(GLuint name) { glDeleteFramebuffers(1, &name); }
inline void delete_vertex_array(GLuint name) { glDeleteVertexArrays(1, &name); }
inline void delete_program(GLuint name) { glDeleteProgram(name); }
inline void delete_shader(GLuint name) { glDeleteShader(name); }
inline void delete_query(GLuint name) { glDeleteQueries(1, &name); }
}  // namespace detail

using Texture = Name<detail::delete_texture>;
using Buffer = Name<detail::delete_buffer>;
using Framebuffer = Name<detail::delete_framebuffer>;
using VertexArray = Name<detail::delete_vertex_array>;
using Program = Name<detail::delete_program>;
using Shader = Name<detail::delete_shader>;
using Query = Name<detail::delete_query>;

inline Texture create_texture(GLenum target) {
  GLuint name = 0;
  glCreateTextures(target, 1, &name);
  return Texture(name);
}
inline Buffer create_buffer() {
  GLuint name = 0;
  glCreateBuffers(1, &name);
  return Buffer(name);
}
inline Framebuffer create_framebuffer() {
  GLuint name = 0;
  glCreateFramebuffers(1, &name);
  return Framebuffer(name);
}
inline Query create_query(GLenum target) {
  GLuint name = 0;
  glCreateQueries(target, 1, &name);
  return Query(name);
}
inline VertexArray create_vertex_array() {
  GLuint name = 0;
  glCreateVertexArrays(1, &name);
  return VertexArray(name);
}

}  // namespace glarelab::gl

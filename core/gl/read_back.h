#pragma once
// Every read-back of GPU data to the host goes through these functions (a test checks that no other
// product file calls glReadPixels, glGetTexImage, glGetTextureImage, glGetTextureSubImage,
// glGetBufferSubData, glGetNamedBufferSubData or glMapBuffer*), so that a process-wide tally counts
// them: how many of each kind and how many bytes. A GPU frame engine that keeps its frames on the GPU
// shows it by this tally (a session's `read_backs` event, docs/DATABASE.md).
//
// Each call site says what it reads back: a whole frame (an image of the frame's or a view's size),
// a kernel (a PSF or its aperture, on the PSF's grid) or a reduction (a few values: sums, a pyramid's
// top cells). Requires a current OpenGL context; the tally itself may be read from any thread.
#include <glad/gl.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace glarelab::gl {

enum class ReadBackKind { frame, kernel, reduction };
inline constexpr std::size_t kReadBackKinds = 3;

struct ReadBackTally {
  std::array<std::uint64_t, kReadBackKinds> calls{};
  std::array<std::uint64_t, kReadBackKinds> bytes{};
  std::uint64_t calls_of(ReadBackKind kind) const { return calls[static_cast<std::size_t>(kind)]; }
  std::uint64_t bytes_of(ReadBackKind kind) const { return bytes[static_cast<std::size_t>(kind)]; }
  // What was read back between `earlier` and this tally.
  ReadBackTally since(const ReadBackTally& earlier) const;
  // "2 frame (16.6 MB), 0 kernel, 3 reduction (96 B)".
  std::string describe() const;
};

// Everything read back in this process so far.
ReadBackTally read_back_tally();

// glGetNamedBufferSubData of `bytes` from `offset` into `data` (waits for the GPU).
void read_back_buffer(GLuint buffer, GLintptr offset, std::size_t bytes, void* data, ReadBackKind kind);
// glReadPixels of a rectangle of `framebuffer` (bound to GL_READ_FRAMEBUFFER) as RGBA floats.
void read_back_framebuffer_rgba(GLuint framebuffer, int x_px, int y_px, int width_px, int height_px, float* data,
                                ReadBackKind kind);
// glGetTextureImage of level 0 of `texture`, `bytes` into `data`.
void read_back_texture(GLuint texture, GLenum format, GLenum type, std::size_t bytes, void* data, ReadBackKind kind);

}  // namespace glarelab::gl

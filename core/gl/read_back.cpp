#include "core/gl/read_back.h"

#include <atomic>

#include "core/number_text.h"

namespace glarelab::gl {
namespace {

std::array<std::atomic<std::uint64_t>, kReadBackKinds> g_calls{};
std::array<std::atomic<std::uint64_t>, kReadBackKinds> g_bytes{};

void count(ReadBackKind kind, std::size_t bytes) {
  const auto k = static_cast<std::size_t>(kind);
  g_calls[k].fetch_add(1, std::memory_order_relaxed);
  g_bytes[k].fetch_add(bytes, std::memory_order_relaxed);
}

std::string byte_text(std::uint64_t bytes) {
  if (bytes >= 1000000) return number_text(static_cast<double>(bytes / 100000) / 10.0) + " MB";
  if (bytes >= 1000) return number_text(static_cast<double>(bytes / 100) / 10.0) + " kB";
  return std::to_string(bytes) + " B";
}

}  // namespace

ReadBackTally ReadBackTally::since(const ReadBackTally& earlier) const {
  ReadBackTally difference;
  for (std::size_t k = 0; k < kReadBackKinds; ++k) {
    difference.calls[k] = calls[k] - earlier.calls[k];
    difference.bytes[k] = bytes[k] - earlier.bytes[k];
  }
  return difference;
}

std::string ReadBackTally::describe() const {
  static constexpr const char* kNames[kReadBackKinds] = {"frame", "kernel", "reduction"};
  std::string text;
  for (std::size_t k = 0; k < kReadBackKinds; ++k) {
    if (k > 0) text += ", ";
    text += std::to_string(calls[k]) + " " + kNames[k];
    if (calls[k] > 0) text += " (" + byte_text(bytes[k]) + ")";
  }
  return text;
}

ReadBackTally read_back_tally() {
  ReadBackTally tally;
  for (std::size_t k = 0; k < kReadBackKinds; ++k) {
    tally.calls[k] = g_calls[k].load(std::memory_order_relaxed);
    tally.bytes[k] = g_bytes[k].load(std::memory_order_relaxed);
  }
  return tally;
}

void read_back_buffer(GLuint buffer, GLintptr offset, std::size_t bytes, void* data, ReadBackKind kind) {
  count(kind, bytes);
  glGetNamedBufferSubData(buffer, offset, static_cast<GLsizeiptr>(bytes), data);
}

void read_back_framebuffer_rgba(GLuint framebuffer, int x_px, int y_px, int width_px, int height_px, float* data,
                                ReadBackKind kind) {
  count(kind, 4 * sizeof(float) * static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(x_px, y_px, width_px, height_px, GL_RGBA, GL_FLOAT, data);
}

void read_back_texture(GLuint texture, GLenum format, GLenum type, std::size_t bytes, void* data, ReadBackKind kind) {
  count(kind, bytes);
  glGetTextureImage(texture, 0, format, type, static_cast<GLsizei>(bytes), data);
}

}  // namespace glarelab::gl

#include "stimuli/perception/gl_frame_buffer.h"

#include <cstddef>
#include <stdexcept>
#include <string>

#include "core/gl/read_back.h"

namespace glarelab::gl {
namespace {

std::size_t float_count(int width_px, int height_px) {
  return 4 * static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px);
}

}  // namespace

GlFrameBuffer::GlFrameBuffer(int width_px, int height_px)
    : width_px_(width_px), height_px_(height_px), buffer_(create_buffer()) {
  if (width_px < 1 || height_px < 1)
    throw std::invalid_argument("perception GL: a frame must be at least 1 x 1 (got " + std::to_string(width_px) +
                                " x " + std::to_string(height_px) + ")");
  // A shader storage block is bounded by the implementation (at least 2^27 bytes in OpenGL 4.5, so
  // 8.4 million pixels, 3840 x 2160, are always accepted); a larger frame would be cut off silently.
  GLint64 max_block_bytes = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block_bytes);
  const std::size_t bytes = float_count(width_px, height_px) * sizeof(float);
  if (bytes > static_cast<std::size_t>(max_block_bytes))
    throw std::invalid_argument("perception GL: a " + std::to_string(width_px) + " x " + std::to_string(height_px) +
                                " frame needs " + std::to_string(bytes) + " bytes of storage buffer, above this "
                                "OpenGL's GL_MAX_SHADER_STORAGE_BLOCK_SIZE of " + std::to_string(max_block_bytes));
  glNamedBufferData(buffer_.get(), static_cast<GLsizeiptr>(bytes), nullptr, GL_DYNAMIC_COPY);
}

GlFrameBuffer::GlFrameBuffer(const ImageRGBA& frame)
    : GlFrameBuffer(frame.empty() ? 0 : frame.width_px, frame.empty() ? 0 : frame.height_px) {
  upload(frame);
}

void GlFrameBuffer::upload(const ImageRGBA& frame) {
  if (frame.width_px != width_px_ || frame.height_px != height_px_ ||
      frame.rgba.size() != float_count(width_px_, height_px_))
    throw std::invalid_argument("perception GL: a " + std::to_string(frame.width_px) + " x " +
                                std::to_string(frame.height_px) + " frame does not fit a " + std::to_string(width_px_) +
                                " x " + std::to_string(height_px_) + " buffer");
  glNamedBufferSubData(buffer_.get(), 0, static_cast<GLsizeiptr>(frame.rgba.size() * sizeof(float)), frame.rgba.data());
}

ImageRGBA GlFrameBuffer::download() const {
  ImageRGBA frame(width_px_, height_px_);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  read_back_buffer(buffer_.get(), 0, frame.rgba.size() * sizeof(float), frame.rgba.data(), ReadBackKind::frame);
  return frame;
}

void GlFrameBuffer::copy_from(GLuint source_buffer) {
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  glCopyNamedBufferSubData(source_buffer, buffer_.get(), 0, 0,
                           static_cast<GLsizeiptr>(float_count(width_px_, height_px_) * sizeof(float)));
}

void dispatch_per_pixel(int width_px, int height_px) {
  glDispatchCompute((static_cast<GLuint>(width_px) + kPerceptionTile - 1) / kPerceptionTile,
                    (static_cast<GLuint>(height_px) + kPerceptionTile - 1) / kPerceptionTile, 1);
}

}  // namespace glarelab::gl

#include "stimuli/gpu_hybrid_finish.h"

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/gl/shader_program.h"

namespace glarelab {
namespace {

void upload(gl::Buffer& buffer, const void* data, std::size_t bytes) {
  if (!buffer) buffer = gl::create_buffer();
  glNamedBufferData(buffer.get(), static_cast<GLsizeiptr>(bytes), data, GL_STATIC_DRAW);
}

}  // namespace

GLuint GpuHybridFinish::finish(GLuint near_buffer, const ImageRGBA& energy, const ImageRGBA& far, const ImageRGBA* ring,
                               double halo_energy, const PixelSolidAngle& solid_angle, std::uint64_t token) {
  const int width = energy.width_px, height = energy.height_px;
  if (far.width_px != width || far.height_px != height || solid_angle.width_px() != width ||
      solid_angle.height_px() != height || (ring != nullptr && (ring->width_px != width || ring->height_px != height)))
    throw std::invalid_argument("hybrid glare on the GPU: the far glare, halo ring and solid angles must be " +
                                std::to_string(width) + " x " + std::to_string(height) + " like the frame");
  if (!program_) program_ = gl::build_program({"stimuli/shaders/hybrid_finish.comp"});
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const std::size_t frame_bytes = 4 * sizeof(float) * pixels;
  if (width != width_px_ || height != height_px_) {
    upload(result_, nullptr, frame_bytes);
    width_px_ = width;
    height_px_ = height;
    uploaded_token_ = ring_token_ = 0;
    weighed_ = nullptr;
  }
  if (token == 0 || token != uploaded_token_) {
    upload(energy_, energy.rgba.data(), frame_bytes);
    upload(far_, far.rgba.data(), frame_bytes);
    uploaded_token_ = token;
  }
  if (ring != nullptr && (token == 0 || token != ring_token_)) {
    upload(ring_, ring->rgba.data(), frame_bytes);
    ring_token_ = token;
  }
  if (weighed_ != &solid_angle) {
    std::vector<float> weights(pixels);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) weights[static_cast<std::size_t>(y) * width + x] = solid_angle.relative(x, y);
    upload(weight_, weights.data(), weights.size() * sizeof(float));
    weighed_ = &solid_angle;
  }
  const GLuint program = program_.get();
  glUseProgram(program);
  glUniform1ui(glGetUniformLocation(program, "uPixels"), static_cast<GLuint>(pixels));
  glUniform1i(glGetUniformLocation(program, "uHalo"), ring != nullptr ? 1 : 0);
  glUniform1f(glGetUniformLocation(program, "uHaloEnergy"), static_cast<float>(halo_energy));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, near_buffer);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, far_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, ring != nullptr ? ring_.get() : energy_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, energy_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, weight_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, result_.get());
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  glDispatchCompute(static_cast<GLuint>((pixels + 255) / 256), 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  glUseProgram(0);
  gl::check_gl_error("hybrid glare: finishing the frame on the GPU");
  return result_.get();
}

}  // namespace glarelab

#include "glare/gl/gl_fft.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "runner/gl/shader_program.h"

namespace glarelab::gl {
namespace {

constexpr GLuint kWorkgroupSize = 64;  // local_size_x of fft_radix2.comp

int log2_exact(int length) {
  int bits = 0;
  while ((1 << bits) < length) ++bits;
  return bits;
}

Buffer complex_buffer(std::size_t elements) {
  Buffer buffer = create_buffer();
  glNamedBufferStorage(buffer.get(), static_cast<GLsizeiptr>(elements * 2 * sizeof(float)), nullptr,
                       GL_DYNAMIC_STORAGE_BIT);
  return buffer;
}

}  // namespace

bool is_supported_fft_length(int length) {
  return length >= kFftMinLength && length <= kFftMaxLength && (length & (length - 1)) == 0;
}

GlFft::GlFft(int width, int height, int layers)
    : width_(width), height_(height), layers_(layers), max_length_(std::max(width, height)) {
  for (const auto& [name, length] : {std::pair{"width", width}, std::pair{"height", height}})
    if (!is_supported_fft_length(length))
      throw std::invalid_argument("GL FFT: " + std::string(name) + " " + std::to_string(length) +
                                  " is not a power of two from " + std::to_string(kFftMinLength) + " to " +
                                  std::to_string(kFftMaxLength));
  if (layers < 1 || layers > 64) throw std::invalid_argument("GL FFT: layer count " + std::to_string(layers) + " is not 1..64");

  program_ = build_program({"glare/shaders/fft_radix2.comp"});
  data_ = complex_buffer(element_count());
  scratch_ = complex_buffer(element_count());

  // exp(-2 pi i m / L_max) for m < L_max / 2, in double, rounded once to float.
  std::vector<float> twiddles(static_cast<std::size_t>(max_length_));
  for (int m = 0; m < max_length_ / 2; ++m) {
    const double angle = 2.0 * std::numbers::pi * m / max_length_;
    twiddles[2 * static_cast<std::size_t>(m)] = static_cast<float>(std::cos(angle));
    twiddles[2 * static_cast<std::size_t>(m) + 1] = static_cast<float>(-std::sin(angle));
  }
  twiddles_ = create_buffer();
  glNamedBufferStorage(twiddles_.get(), static_cast<GLsizeiptr>(twiddles.size() * sizeof(float)), twiddles.data(), 0);

  const GLuint p = program_.get();
  length_location_ = glGetUniformLocation(p, "uLength");
  span_location_ = glGetUniformLocation(p, "uSpan");
  twiddle_stride_location_ = glGetUniformLocation(p, "uTwiddleStride");
  axis_stride_location_ = glGetUniformLocation(p, "uAxisStride");
  line_stride_location_ = glGetUniformLocation(p, "uLineStride");
  lines_location_ = glGetUniformLocation(p, "uLines");
  layer_stride_location_ = glGetUniformLocation(p, "uLayerStride");
  conjugate_location_ = glGetUniformLocation(p, "uConjugate");
  scale_location_ = glGetUniformLocation(p, "uScale");
  check_gl_error("GL FFT: creating buffers and program");
}

std::size_t GlFft::element_count() const {
  return static_cast<std::size_t>(layers_) * static_cast<std::size_t>(height_) * static_cast<std::size_t>(width_);
}

void GlFft::run_axis(bool rows, float conjugate, bool scale_last_pass) {
  const int length = rows ? width_ : height_;
  const int lines = rows ? height_ : width_;
  const int passes = log2_exact(length);
  glUniform1ui(length_location_, static_cast<GLuint>(length));
  glUniform1ui(axis_stride_location_, rows ? 1u : static_cast<GLuint>(width_));
  glUniform1ui(line_stride_location_, rows ? static_cast<GLuint>(width_) : 1u);
  glUniform1ui(lines_location_, static_cast<GLuint>(lines));
  glUniform1ui(layer_stride_location_, static_cast<GLuint>(width_ * height_));
  glUniform1f(conjugate_location_, conjugate);
  const GLuint groups_x = (static_cast<GLuint>(length / 2) + kWorkgroupSize - 1) / kWorkgroupSize;
  for (int pass = 0; pass < passes; ++pass) {
    const int span = 1 << pass;
    glUniform1ui(span_location_, static_cast<GLuint>(span));
    glUniform1ui(twiddle_stride_location_, static_cast<GLuint>(max_length_ / (2 * span)));
    const bool last = pass == passes - 1;
    glUniform1f(scale_location_,
                scale_last_pass && last ? static_cast<float>(1.0 / (static_cast<double>(width_) * height_)) : 1.0f);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, data_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, scratch_.get());
    glDispatchCompute(groups_x, static_cast<GLuint>(lines), static_cast<GLuint>(layers_));
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    std::swap(data_, scratch_);
  }
}

void GlFft::transform(FftDirection direction) {
  glUseProgram(program_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, twiddles_.get());
  const bool inverse = direction == FftDirection::inverse;
  const float conjugate = inverse ? -1.0f : 1.0f;
  run_axis(true, conjugate, false);
  run_axis(false, conjugate, inverse);
  glUseProgram(0);
  check_gl_error("GL FFT: transform");
}

void GlFft::upload(const std::vector<std::complex<float>>& values) {
  if (values.size() != element_count())
    throw std::invalid_argument("GL FFT: upload of " + std::to_string(values.size()) + " values into a grid of " +
                                std::to_string(element_count()));
  glNamedBufferSubData(data_.get(), 0, static_cast<GLsizeiptr>(values.size() * sizeof(std::complex<float>)),
                       values.data());
  check_gl_error("GL FFT: upload");
}

std::vector<std::complex<float>> GlFft::download() const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<std::complex<float>> values(element_count());
  glGetNamedBufferSubData(data_.get(), 0, static_cast<GLsizeiptr>(values.size() * sizeof(std::complex<float>)),
                          values.data());
  check_gl_error("GL FFT: download");
  return values;
}

}  // namespace glarelab::gl

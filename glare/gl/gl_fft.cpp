#include "glare/gl/gl_fft.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/gl/shader_program.h"

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

  radix2_ = make_pass("glare/shaders/fft_radix2.comp");
  radix4_ = make_pass("glare/shaders/fft_radix4.comp");
  data_ = complex_buffer(element_count());
  scratch_ = complex_buffer(element_count());

  // exp(-2 pi i m / L_max) for m < L_max (radix 4 needs r k < 4 Ns <= L_max), in double, rounded
  // once to float.
  std::vector<float> twiddles(2 * static_cast<std::size_t>(max_length_));
  for (int m = 0; m < max_length_; ++m) {
    const double angle = 2.0 * std::numbers::pi * m / max_length_;
    twiddles[2 * static_cast<std::size_t>(m)] = static_cast<float>(std::cos(angle));
    twiddles[2 * static_cast<std::size_t>(m) + 1] = static_cast<float>(-std::sin(angle));
  }
  twiddles_ = create_buffer();
  glNamedBufferStorage(twiddles_.get(), static_cast<GLsizeiptr>(twiddles.size() * sizeof(float)), twiddles.data(), 0);
  check_gl_error("GL FFT: creating buffers and program");
}

std::size_t GlFft::element_count() const {
  return static_cast<std::size_t>(layers_) * static_cast<std::size_t>(height_) * static_cast<std::size_t>(width_);
}

GlFft::Pass GlFft::make_pass(const char* shader_path) {
  Pass pass;
  pass.program = build_program({shader_path});
  const GLuint p = pass.program.get();
  pass.length = glGetUniformLocation(p, "uLength");
  pass.span = glGetUniformLocation(p, "uSpan");
  pass.twiddle_stride = glGetUniformLocation(p, "uTwiddleStride");
  pass.axis_stride = glGetUniformLocation(p, "uAxisStride");
  pass.line_stride = glGetUniformLocation(p, "uLineStride");
  pass.lines = glGetUniformLocation(p, "uLines");
  pass.layer_stride = glGetUniformLocation(p, "uLayerStride");
  pass.conjugate = glGetUniformLocation(p, "uConjugate");
  pass.scale = glGetUniformLocation(p, "uScale");
  pass.lines_along_x = glGetUniformLocation(p, "uLinesAlongX");
  return pass;
}

void GlFft::run_axis(bool rows, float conjugate, bool scale_last_pass) {
  const int length = rows ? width_ : height_;
  const int lines = rows ? height_ : width_;
  const int bits = log2_exact(length);
  const auto groups_of = [](int count) { return (static_cast<GLuint>(count) + kWorkgroupSize - 1) / kWorkgroupSize; };
  // Odd powers of two: one radix-2 pass (Ns = 1), then radix 4 (Ns = 2, 8, ...); even: radix 4 only.
  int span = 1;
  while (span < length) {
    const int radix = (bits % 2 == 1 && span == 1) ? 2 : 4;
    const Pass& pass = radix == 2 ? radix2_ : radix4_;
    const int butterflies = length / radix;
    glUseProgram(pass.program.get());
    glUniform1ui(pass.length, static_cast<GLuint>(length));
    glUniform1ui(pass.axis_stride, rows ? 1u : static_cast<GLuint>(width_));
    glUniform1ui(pass.line_stride, rows ? static_cast<GLuint>(width_) : 1u);
    glUniform1ui(pass.lines, static_cast<GLuint>(lines));
    glUniform1ui(pass.layer_stride, static_cast<GLuint>(width_ * height_));
    glUniform1f(pass.conjugate, conjugate);
    // Rows: invocations along x walk the butterflies of one row (contiguous). Columns: they walk
    // across columns, so a workgroup reads 64 adjacent elements of a row, not 64 rows apart.
    glUniform1i(pass.lines_along_x, rows ? 0 : 1);
    glUniform1ui(pass.span, static_cast<GLuint>(span));
    glUniform1ui(pass.twiddle_stride, static_cast<GLuint>(max_length_ / (radix * span)));
    const bool last = span * radix == length;
    glUniform1f(pass.scale,
                scale_last_pass && last ? static_cast<float>(1.0 / (static_cast<double>(width_) * height_)) : 1.0f);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, data_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, scratch_.get());
    const GLuint groups_x = rows ? groups_of(butterflies) : groups_of(lines);
    const GLuint groups_y = rows ? static_cast<GLuint>(lines) : static_cast<GLuint>(butterflies);
    glDispatchCompute(groups_x, groups_y, static_cast<GLuint>(layers_));
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    std::swap(data_, scratch_);
    span *= radix;
  }
}

void GlFft::transform(FftDirection direction) {
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

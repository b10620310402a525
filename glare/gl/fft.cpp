#include "glare/gl/fft.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/gl/read_back.h"
#include "core/gl/shader_program.h"

namespace glarelab::gl {
namespace {

// Complex values one workgroup holds in shared memory: the 32 KiB OpenGL 4.5 guarantees
// (GL_MAX_COMPUTE_SHARED_MEMORY_SIZE is at least 32768), so the longest line, 4096, fits.
constexpr int kSharedElements = 4096;
constexpr int kMaxThreads = 256;  // per workgroup; OpenGL guarantees 1024

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

  rows_ = make_axis_pass(width, std::min(height, kSharedElements / width));
  columns_ = make_axis_pass(height, std::min(width, kSharedElements / height));
  data_ = complex_buffer(element_count());

  // exp(-2 pi i m / L_max) for m < L_max (radix 4 needs r k < 4 Ns <= L), in double, rounded
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

GlFft::AxisPass GlFft::make_axis_pass(int length, int lines) {
  AxisPass pass;
  pass.lines_per_group = lines;
  const int threads = std::max(1, std::min(kMaxThreads, length * lines / 4));
  pass.program = build_program({"glare/shaders/fft_lines_shared.comp"},
                               "#define LENGTH " + std::to_string(length) + "\n#define LINES " + std::to_string(lines) +
                                   "\n#define THREADS " + std::to_string(threads) + "\n");
  const GLuint p = pass.program.get();
  pass.axis_stride = glGetUniformLocation(p, "uAxisStride");
  pass.line_stride = glGetUniformLocation(p, "uLineStride");
  pass.layer_stride = glGetUniformLocation(p, "uLayerStride");
  pass.twiddle_length = glGetUniformLocation(p, "uTwiddleLength");
  pass.lines_along_x = glGetUniformLocation(p, "uLinesAlongX");
  pass.conjugate = glGetUniformLocation(p, "uConjugate");
  pass.scale = glGetUniformLocation(p, "uScale");
  return pass;
}

void GlFft::run_axis(const AxisPass& pass, bool rows, float conjugate, float scale) const {
  const int lines = rows ? height_ : width_;
  glUseProgram(pass.program.get());
  glUniform1ui(pass.axis_stride, rows ? 1u : static_cast<GLuint>(width_));
  glUniform1ui(pass.line_stride, rows ? static_cast<GLuint>(width_) : 1u);
  glUniform1ui(pass.layer_stride, static_cast<GLuint>(width_ * height_));
  glUniform1ui(pass.twiddle_length, static_cast<GLuint>(max_length_));
  // Columns: a workgroup's lines are adjacent columns, so its invocations read across a row.
  glUniform1i(pass.lines_along_x, rows ? 0 : 1);
  glUniform1f(pass.conjugate, conjugate);
  glUniform1f(pass.scale, scale);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, data_.get());
  // Lengths and line counts are powers of two, so the workgroups tile the lines exactly.
  glDispatchCompute(static_cast<GLuint>(lines / pass.lines_per_group), static_cast<GLuint>(layers_), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void GlFft::transform(FftDirection direction) {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, twiddles_.get());
  const bool inverse = direction == FftDirection::inverse;
  const float conjugate = inverse ? -1.0f : 1.0f;
  run_axis(rows_, true, conjugate, 1.0f);
  run_axis(columns_, false, conjugate, inverse ? static_cast<float>(1.0 / (static_cast<double>(width_) * height_)) : 1.0f);
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
  read_back_buffer(data_.get(), 0, values.size() * sizeof(std::complex<float>), values.data(), ReadBackKind::kernel);
  check_gl_error("GL FFT: download");
  return values;
}

}  // namespace glarelab::gl

#include "glare/gl/fft.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/fft_size.h"
#include "core/gl/read_back.h"
#include "core/gl/shader_program.h"

namespace glarelab::gl {
namespace {

// Complex values one workgroup holds in shared memory: the 32 KiB OpenGL 4.5 guarantees
// (GL_MAX_COMPUTE_SHARED_MEMORY_SIZE is at least 32768), so the longest line, 4096, fits.
constexpr int kSharedElements = 4096;
constexpr int kMaxThreads = 256;  // per workgroup; OpenGL guarantees 1024

// The lines one workgroup transforms: as many as fit in shared memory and divide the line count.
int lines_per_group(int length, int line_count) {
  int lines = std::max(1, std::min(line_count, kSharedElements / length));
  while (line_count % lines != 0) --lines;
  return lines;
}

Buffer complex_buffer(std::size_t elements) {
  Buffer buffer = create_buffer();
  glNamedBufferStorage(buffer.get(), static_cast<GLsizeiptr>(elements * 2 * sizeof(float)), nullptr,
                       GL_DYNAMIC_STORAGE_BIT);
  return buffer;
}

}  // namespace

bool is_supported_fft_length(int length) {
  return length >= kFftMinLength && length <= kFftMaxLength && smooth_fft_size(length) == length;
}

bool is_power_of_two_fft_length(int length) {
  return length >= kFftMinLength && length <= kFftMaxLength && (length & (length - 1)) == 0;
}

std::vector<int> fft_radices(int length) {
  if (!is_supported_fft_length(length)) return {};
  std::vector<int> radices;
  int twos = 0;
  while (length % 2 == 0) {
    length /= 2;
    ++twos;
  }
  // Radix 4 while two factors of 2 are left: the fewest stages, so the fewest barriers and trips
  // through shared memory; then the odd 2, the 3s and the 5s.
  for (; twos >= 2; twos -= 2) radices.push_back(4);
  if (twos == 1) radices.push_back(2);
  for (const int factor : {3, 5})
    for (; length % factor == 0; length /= factor) radices.push_back(factor);
  return radices;
}

GlFft::GlFft(int width, int height, int layers)
    : width_(width), height_(height), layers_(layers) {
  for (const auto& [name, length] : {std::pair{"width", width}, std::pair{"height", height}})
    if (!is_supported_fft_length(length))
      throw std::invalid_argument("GL FFT: " + std::string(name) + " " + std::to_string(length) +
                                  " is not a product of 2s, 3s and 5s from " + std::to_string(kFftMinLength) + " to " +
                                  std::to_string(kFftMaxLength));
  if (layers < 1 || layers > 64) throw std::invalid_argument("GL FFT: layer count " + std::to_string(layers) + " is not 1..64");

  rows_ = make_axis_pass(width, lines_per_group(width, height));
  columns_ = make_axis_pass(height, lines_per_group(height, width));
  data_ = complex_buffer(element_count());
  check_gl_error("GL FFT: creating buffers and program");
}

std::size_t GlFft::element_count() const {
  return static_cast<std::size_t>(layers_) * static_cast<std::size_t>(height_) * static_cast<std::size_t>(width_);
}

GlFft::AxisPass GlFft::make_axis_pass(int length, int lines) {
  AxisPass pass;
  pass.lines_per_group = lines;
  // About four elements an invocation, in whole warps of 32, at most kMaxThreads.
  const int threads = std::clamp((length * lines / 4 + 31) / 32 * 32, 32, kMaxThreads);
  std::string stages;
  int span = 1;
  for (const int radix : fft_radices(length)) {
    stages += " STAGE(" + std::to_string(radix) + "u, " + std::to_string(span) + "u)";
    span *= radix;
  }
  pass.program = build_program({"glare/shaders/fft_lines_shared.comp"},
                               "#define LENGTH " + std::to_string(length) + "\n#define LINES " + std::to_string(lines) +
                                   "\n#define THREADS " + std::to_string(threads) + "\n#define STAGE_LIST" + stages + "\n");
  const GLuint p = pass.program.get();
  pass.axis_stride = glGetUniformLocation(p, "uAxisStride");
  pass.line_stride = glGetUniformLocation(p, "uLineStride");
  pass.layer_stride = glGetUniformLocation(p, "uLayerStride");
  pass.lines_along_x = glGetUniformLocation(p, "uLinesAlongX");
  pass.conjugate = glGetUniformLocation(p, "uConjugate");
  pass.scale = glGetUniformLocation(p, "uScale");
  // exp(-2 pi i m / L) for m < L (a stage reads r k L / (R Ns) < L), in double, rounded once to float.
  std::vector<float> twiddles(2 * static_cast<std::size_t>(length));
  for (int m = 0; m < length; ++m) {
    const double angle = 2.0 * std::numbers::pi * m / length;
    twiddles[2 * static_cast<std::size_t>(m)] = static_cast<float>(std::cos(angle));
    twiddles[2 * static_cast<std::size_t>(m) + 1] = static_cast<float>(-std::sin(angle));
  }
  pass.twiddles = create_buffer();
  glNamedBufferStorage(pass.twiddles.get(), static_cast<GLsizeiptr>(twiddles.size() * sizeof(float)), twiddles.data(), 0);
  return pass;
}

void GlFft::run_axis(const AxisPass& pass, bool rows, float conjugate, float scale) const {
  const int lines = rows ? height_ : width_;
  glUseProgram(pass.program.get());
  glUniform1ui(pass.axis_stride, rows ? 1u : static_cast<GLuint>(width_));
  glUniform1ui(pass.line_stride, rows ? static_cast<GLuint>(width_) : 1u);
  glUniform1ui(pass.layer_stride, static_cast<GLuint>(width_ * height_));
  // Columns: a workgroup's lines are adjacent columns, so its invocations read across a row.
  glUniform1i(pass.lines_along_x, rows ? 0 : 1);
  glUniform1f(pass.conjugate, conjugate);
  glUniform1f(pass.scale, scale);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, data_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, pass.twiddles.get());
  // lines_per_group divides the line count (lines_per_group()), so the workgroups tile the lines.
  glDispatchCompute(static_cast<GLuint>(lines / pass.lines_per_group), static_cast<GLuint>(layers_), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void GlFft::transform(FftDirection direction) {
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

#pragma once
// 2D complex-to-complex FFT on the GPU by OpenGL 4.5 compute shaders: rows, then columns, each axis
// one dispatch of glare/shaders/fft_lines_shared.comp (a workgroup transforms whole lines in shared
// memory by Stockham stages of radix 4, 2, 3 and 5), in place on a
// std430 shader storage buffer of vec2 (real, imaginary) holding `layers` grids of width x height,
// layer-major, row-major, row 0 first.
// Same sign convention as FFTW: forward X[k] = sum_n x[n] exp(-2 pi i k n / L); the inverse is
// scaled by 1 / (width * height), so inverse(forward(x)) = x.
// Twiddle factors are computed in double precision on the CPU and uploaded as floats.
// A current OpenGL 4.5 context is required (core/gl/gl_context.h); not thread-safe.
#include <complex>
#include <vector>

#include "core/gl/gl_objects.h"

namespace glarelab::gl {

enum class FftDirection { forward, inverse };

// Lengths the GL FFT accepts along either axis: 2^a 3^b 5^c from 16 to 4096, so that a convolution's
// padded grid fits its frame (glare/gl/convolution.h, padded_fft_length). The GL PSF's grids are the
// powers of two among them (is_power_of_two_fft_length; glare/gl/psf.h).
constexpr int kFftMinLength = 16;
constexpr int kFftMaxLength = 4096;
bool is_supported_fft_length(int length);
bool is_power_of_two_fft_length(int length);
// The radices of the stages that transform a line of `length` (empty when it is not supported):
// 4s while two factors of 2 are left, then a 2, the 3s and the 5s; their product is `length`.
std::vector<int> fft_radices(int length);

class GlFft {
 public:
  // Throws std::invalid_argument("GL FFT: ...") for an unsupported width, height or layer count.
  GlFft(int width, int height, int layers = 1);

  int width() const { return width_; }
  int height() const { return height_; }
  int layers() const { return layers_; }
  std::size_t element_count() const;  // layers * height * width

  // The buffer that holds the data (input before transform(), output after, in place). Other
  // passes write into it and read from it directly.
  GLuint data() const { return data_.get(); }

  void transform(FftDirection direction);

  void upload(const std::vector<std::complex<float>>& values);  // element_count() values
  std::vector<std::complex<float>> download() const;

 private:
  // The program that transforms every line along one axis, specialised for its length and the
  // lines one workgroup takes, and its uniform locations.
  struct AxisPass {
    Program program;
    Buffer twiddles;  // exp(-2 pi i m / length), m < length
    int lines_per_group = 1;
    GLint axis_stride, line_stride, layer_stride, lines_along_x, conjugate, scale;
  };
  static AxisPass make_axis_pass(int length, int lines);
  void run_axis(const AxisPass& pass, bool rows, float conjugate, float scale) const;

  int width_;
  int height_;
  int layers_;
  AxisPass rows_;
  AxisPass columns_;
  Buffer data_;
};

}  // namespace glarelab::gl

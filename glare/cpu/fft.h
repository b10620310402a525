#pragma once
// FFTW3 transforms for the CPU glare path (libfftw3-dev: fftw3 double, fftw3f float). Double is the
// reference; float is for speed. Plans use FFTW_ESTIMATE: no timing-dependent planning, so the same
// input gives the same output on every run. FFTW's planner is not thread-safe; plan creation is
// serialised here, execution is not.
#include <complex>
#include <vector>

namespace glarelab {

enum class FftPrecision { float32, float64 };
const char* fft_precision_name(FftPrecision precision);

// In-place forward 2D DFT (exponent sign -1, unnormalised) of a rows x cols row-major array.
void fft2d_forward(std::vector<std::complex<double>>& data, int rows, int cols);
void fft2d_forward(std::vector<std::complex<float>>& data, int rows, int cols);

// Real-input circular convolution kernels: forward real-to-complex (rows x (cols/2+1) output) and
// the inverse complex-to-real, unnormalised (the caller divides by rows * cols).
std::vector<std::complex<double>> fft2d_real_forward(std::vector<double>& real, int rows, int cols);
void fft2d_real_inverse(std::vector<std::complex<double>>& spectrum, std::vector<double>& real, int rows, int cols);
std::vector<std::complex<float>> fft2d_real_forward(std::vector<float>& real, int rows, int cols);
void fft2d_real_inverse(std::vector<std::complex<float>>& spectrum, std::vector<float>& real, int rows, int cols);

}  // namespace glarelab

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

// Smallest n' >= n whose prime factors are 2, 3, 5 and 7 (sizes FFTW handles fastest).
int good_fft_size(int n);
// Smallest n' >= n whose prime factors are 2, 3 and 5: without 7, whose codelets FFTW runs slower
// per value (FFTW_MEASURE plans of the convolution's 3 x 1029 x 1296 grid took 1.7 times those of
// 3 x 1024 x 1200 on the bench's machine, for 9 % more values).
int smooth_fft_size(int n);

}  // namespace glarelab

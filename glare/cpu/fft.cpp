#include "glare/cpu/fft.h"

#include <fftw3.h>

#include "glare/cpu/fftw_float_plan.h"

#include <mutex>
#include <stdexcept>

namespace glarelab {
namespace {

// One planner lock for every FFTW plan of the program (glare/cpu/fftw_float_plan.h owns it).
std::mutex& planner_mutex() { return fftw_planner_mutex(); }

void check_size(std::size_t size, int rows, int cols, const char* what) {
  if (rows <= 0 || cols <= 0 || size != static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols))
    throw std::invalid_argument(std::string("glare/cpu/fft: ") + what + ": array size does not match rows x cols");
}

}  // namespace

const char* fft_precision_name(FftPrecision precision) {
  return precision == FftPrecision::float32 ? "float32" : "float64";
}

void fft2d_forward(std::vector<std::complex<double>>& data, int rows, int cols) {
  check_size(data.size(), rows, cols, "fft2d_forward");
  auto* buffer = reinterpret_cast<fftw_complex*>(data.data());
  fftw_plan plan;
  {
    std::lock_guard lock(planner_mutex());
    plan = fftw_plan_dft_2d(rows, cols, buffer, buffer, FFTW_FORWARD, FFTW_ESTIMATE);
  }
  if (plan == nullptr) throw std::runtime_error("glare/cpu/fft: FFTW could not plan a double 2D FFT");
  fftw_execute(plan);
  std::lock_guard lock(planner_mutex());
  fftw_destroy_plan(plan);
}

void fft2d_forward(std::vector<std::complex<float>>& data, int rows, int cols) {
  check_size(data.size(), rows, cols, "fft2d_forward");
  auto* buffer = reinterpret_cast<fftwf_complex*>(data.data());
  fftwf_plan plan;
  {
    std::lock_guard lock(planner_mutex());
    plan = fftwf_plan_dft_2d(rows, cols, buffer, buffer, FFTW_FORWARD, FFTW_ESTIMATE);
  }
  if (plan == nullptr) throw std::runtime_error("glare/cpu/fft: FFTW could not plan a float 2D FFT");
  fftwf_execute(plan);
  std::lock_guard lock(planner_mutex());
  fftwf_destroy_plan(plan);
}

std::vector<std::complex<double>> fft2d_real_forward(std::vector<double>& real, int rows, int cols) {
  check_size(real.size(), rows, cols, "fft2d_real_forward");
  std::vector<std::complex<double>> spectrum(static_cast<std::size_t>(rows) * (cols / 2 + 1));
  fftw_plan plan;
  {
    std::lock_guard lock(planner_mutex());
    plan = fftw_plan_dft_r2c_2d(rows, cols, real.data(), reinterpret_cast<fftw_complex*>(spectrum.data()),
                                FFTW_ESTIMATE);
  }
  if (plan == nullptr) throw std::runtime_error("glare/cpu/fft: FFTW could not plan a double real 2D FFT");
  fftw_execute(plan);
  std::lock_guard lock(planner_mutex());
  fftw_destroy_plan(plan);
  return spectrum;
}

void fft2d_real_inverse(std::vector<std::complex<double>>& spectrum, std::vector<double>& real, int rows, int cols) {
  check_size(spectrum.size(), rows, cols / 2 + 1, "fft2d_real_inverse");
  real.assign(static_cast<std::size_t>(rows) * cols, 0.0);
  fftw_plan plan;
  {
    std::lock_guard lock(planner_mutex());
    // FFTW_DESTROY_INPUT is the default for c2r; the spectrum is scratch afterwards.
    plan = fftw_plan_dft_c2r_2d(rows, cols, reinterpret_cast<fftw_complex*>(spectrum.data()), real.data(),
                                FFTW_ESTIMATE);
  }
  if (plan == nullptr) throw std::runtime_error("glare/cpu/fft: FFTW could not plan a double inverse real 2D FFT");
  fftw_execute(plan);
  std::lock_guard lock(planner_mutex());
  fftw_destroy_plan(plan);
}

std::vector<std::complex<float>> fft2d_real_forward(std::vector<float>& real, int rows, int cols) {
  check_size(real.size(), rows, cols, "fft2d_real_forward");
  std::vector<std::complex<float>> spectrum(static_cast<std::size_t>(rows) * (cols / 2 + 1));
  fftwf_plan plan;
  {
    std::lock_guard lock(planner_mutex());
    plan = fftwf_plan_dft_r2c_2d(rows, cols, real.data(), reinterpret_cast<fftwf_complex*>(spectrum.data()),
                                 FFTW_ESTIMATE);
  }
  if (plan == nullptr) throw std::runtime_error("glare/cpu/fft: FFTW could not plan a float real 2D FFT");
  fftwf_execute(plan);
  std::lock_guard lock(planner_mutex());
  fftwf_destroy_plan(plan);
  return spectrum;
}

void fft2d_real_inverse(std::vector<std::complex<float>>& spectrum, std::vector<float>& real, int rows, int cols) {
  check_size(spectrum.size(), rows, cols / 2 + 1, "fft2d_real_inverse");
  real.assign(static_cast<std::size_t>(rows) * cols, 0.0f);
  fftwf_plan plan;
  {
    std::lock_guard lock(planner_mutex());
    plan = fftwf_plan_dft_c2r_2d(rows, cols, reinterpret_cast<fftwf_complex*>(spectrum.data()), real.data(),
                                 FFTW_ESTIMATE);
  }
  if (plan == nullptr) throw std::runtime_error("glare/cpu/fft: FFTW could not plan a float inverse real 2D FFT");
  fftwf_execute(plan);
  std::lock_guard lock(planner_mutex());
  fftwf_destroy_plan(plan);
}

}  // namespace glarelab

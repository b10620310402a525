#include "glare/cpu/fftw_double_plan.h"

#include <fftw3.h>

#include <mutex>
#include <stdexcept>

#include "glare/cpu/fftw_float_plan.h"

namespace glarelab {

void FftwDoublePlan::Destroy::operator()(fftw_plan_s* plan) const {
  std::lock_guard lock(fftw_planner_mutex());
  fftw_destroy_plan(plan);
}

FftwDoublePlan FftwDoublePlan::complex_row_forward(int length, std::complex<double>* in, std::complex<double>* out) {
  const bool rows_keep_alignment = (static_cast<std::size_t>(length) * sizeof(std::complex<double>)) % 64 == 0;
  fftw_plan plan = nullptr;
  {
    std::lock_guard lock(fftw_planner_mutex());
    plan = fftw_plan_dft_1d(length, reinterpret_cast<fftw_complex*>(in), reinterpret_cast<fftw_complex*>(out),
                            FFTW_FORWARD, FFTW_ESTIMATE | (rows_keep_alignment ? 0u : FFTW_UNALIGNED));
  }
  if (plan == nullptr) throw std::runtime_error("glare/cpu/fftw_double_plan: FFTW could not plan a double complex row FFT");
  return FftwDoublePlan(plan);
}

FftwDoublePlan FftwDoublePlan::measured_complex_forward(int rows, int cols, std::complex<double>* in,
                                                        std::complex<double>* out) {
  fftw_plan plan = nullptr;
  {
    std::lock_guard lock(fftw_planner_mutex());
    plan = fftw_plan_dft_2d(rows, cols, reinterpret_cast<fftw_complex*>(in), reinterpret_cast<fftw_complex*>(out),
                            FFTW_FORWARD, FFTW_MEASURE);
    fftw_forget_wisdom();
  }
  if (plan == nullptr) throw std::runtime_error("glare/cpu/fftw_double_plan: FFTW could not plan a double 2D FFT");
  return FftwDoublePlan(plan);
}

void FftwDoublePlan::execute() const {
  if (plan_ == nullptr) throw std::logic_error("glare/cpu/fftw_double_plan: executing an empty plan");
  fftw_execute(plan_.get());
}

void FftwDoublePlan::execute(std::complex<double>* in, std::complex<double>* out) const {
  if (plan_ == nullptr) throw std::logic_error("glare/cpu/fftw_double_plan: executing an empty plan");
  fftw_execute_dft(plan_.get(), reinterpret_cast<fftw_complex*>(in), reinterpret_cast<fftw_complex*>(out));
}

}  // namespace glarelab

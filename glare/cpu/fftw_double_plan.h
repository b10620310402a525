#pragma once
// FFTW double plans made once and run many times: the float64 row transforms of the planned CPU path
// (glare/cpu/pupil_spectrum.h's spectral PSF), FFTW_ESTIMATE and single-threaded (the caller shares
// the rows among its own threads), so the same input gives the same output on every run; and the
// measured 2D plan of their floor (glare/cpu/fftw_floor.h). Planning and destroying take
// fftw_planner_mutex() (glare/cpu/fftw_float_plan.h), executing does not.
#include <complex>
#include <memory>

struct fftw_plan_s;

namespace glarelab {

// A plan that owns its fftw_plan; move-only.
class FftwDoublePlan {
 public:
  FftwDoublePlan() = default;

  // One forward complex DFT of `length` values (exponent sign -1, unnormalised), out of place, made
  // to be run by execute(in, out) on any row of two arrays of such rows; planned FFTW_UNALIGNED
  // unless a row's bytes are a multiple of 64, where every row keeps fftw_malloc's alignment.
  static FftwDoublePlan complex_row_forward(int length, std::complex<double>* in, std::complex<double>* out);
  void execute(std::complex<double>* in, std::complex<double>* out) const;

  // A forward complex rows x cols DFT, out of place, on one thread, the fastest FFTW times
  // (FFTW_MEASURE; it overwrites its arrays while planning). FFTW double's wisdom is forgotten after
  // it, so that the estimated plans above (and glare/cpu/fft.cpp's) stay the plans they are.
  static FftwDoublePlan measured_complex_forward(int rows, int cols, std::complex<double>* in, std::complex<double>* out);
  void execute() const;  // on the arrays it was planned with

 private:
  struct Destroy {  // under fftw_planner_mutex(), as planning
    void operator()(fftw_plan_s* plan) const;
  };
  explicit FftwDoublePlan(fftw_plan_s* plan) : plan_(plan) {}
  std::unique_ptr<fftw_plan_s, Destroy> plan_;
};

}  // namespace glarelab

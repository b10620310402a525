#include "glare/cpu/fftw_float_plan.h"

#include "core/chunk_pool.h"
#include "glare/cpu/fftw_wisdom.h"

#include <fftw3.h>

#include <algorithm>
#include <cstddef>
#include <new>
#include <stdexcept>
#include <string>

namespace glarelab {
namespace {

// Plans with `threads` FFTW threads, then puts the planner back to one thread: the plans of
// glare/cpu/fft.cpp (made per call) stay single-threaded, as they were.
// make_plan(flags) gets the planning's FFTW flags (fftwf_plan_s* (unsigned)).
template <typename MakePlan>
fftwf_plan_s* plan_with_threads(int threads, const char* what, FftwPlanning planning, MakePlan&& make_plan) {
  std::lock_guard lock(fftw_planner_mutex());  // which has set up FFTW's threads
  fftwf_plan_with_nthreads(std::max(1, threads));
  fftwf_plan plan = nullptr;
  if (planning == FftwPlanning::kept)
    plan = plan_with_kept_wisdom(make_plan);
  else
    plan = make_plan(planning == FftwPlanning::measure ? FFTW_MEASURE : FFTW_ESTIMATE);
  fftwf_plan_with_nthreads(1);
  if (plan == nullptr) throw std::runtime_error(std::string("glare/cpu/fftw_float_plan: FFTW could not plan ") + what);
  return plan;
}

// FFTW's parallel loops run on core's chunk pool (fftwf_threads_set_callback, FFTW 3.3.9; the
// manual's "Usage of Multi-threaded FFTW"), not on FFTW's own threads: the jobs are FFTW's, each run
// once, so a transform's result is the same. The pool runs a caller's chunks at the caller's
// niceness (core/chunk_pool.h), so a frame computed below the display's priority (the trial
// prepared ahead, runner/session/trial_ahead.cpp) does not lend its transforms to threads at the
// display's.
void run_fftw_jobs(void* (*work)(char*), char* jobdata, std::size_t elsize, int njobs, void*) {
  run_chunks(njobs, [&](int job) { work(jobdata + elsize * static_cast<std::size_t>(job)); });
}

}  // namespace

std::mutex& fftw_planner_mutex() {
  static std::mutex mutex;
  // FFTW float's threads are set up before its planner is first used, by any plan (glare/cpu/fft.cpp's
  // per-call plans too; every planning takes this mutex first). A planner made before
  // fftwf_init_threads has another configuration, and wisdom carries the configuration as its
  // signature: wisdom written by a process that planned (or set a time limit) first could not be read
  // by one that set up threads first, and the kept plans (glare/cpu/fftw_wisdom.h) would be measured again.
  static const bool threads_ready = [] {
    if (fftwf_init_threads() == 0) return false;
    fftwf_threads_set_callback(&run_fftw_jobs, nullptr);
    return true;
  }();
  if (!threads_ready) throw std::runtime_error("glare/cpu/fftw_float_plan: fftwf_init_threads failed");
  return mutex;
}

void forget_fftw_float_wisdom() {
  std::lock_guard lock(fftw_planner_mutex());
  fftwf_forget_wisdom();
}

template <typename T>
FftwFloatBuffer<T>::FftwFloatBuffer(std::size_t count)
    : data_(static_cast<T*>(fftwf_malloc(std::max<std::size_t>(1, count * sizeof(T))))), size_(count) {
  if (!data_) throw std::bad_alloc();
  for (std::size_t k = 0; k < count; ++k) data_[k] = T{};
}

template <typename T>
void FftwFloatBuffer<T>::Free::operator()(T* pointer) const {
  fftwf_free(pointer);
}

template class FftwFloatBuffer<float>;
template class FftwFloatBuffer<std::complex<float>>;
// fftwf_malloc aligns as fftw_malloc does, so the float64 transforms' buffers (glare/cpu/pupil_spectrum.h)
// are the same class.
template class FftwFloatBuffer<double>;
template class FftwFloatBuffer<std::complex<double>>;

FftwFloatPlan::FftwFloatPlan(FftwFloatPlan&& other) noexcept : plan_(other.plan_) { other.plan_ = nullptr; }

FftwFloatPlan& FftwFloatPlan::operator=(FftwFloatPlan&& other) noexcept {
  if (this != &other) {
    FftwFloatPlan old(std::move(*this));
    plan_ = other.plan_;
    other.plan_ = nullptr;
  }
  return *this;
}

FftwFloatPlan::~FftwFloatPlan() {
  if (plan_ == nullptr) return;
  std::lock_guard lock(fftw_planner_mutex());
  fftwf_destroy_plan(plan_);
}

void FftwFloatPlan::execute() const {
  if (plan_ == nullptr) throw std::logic_error("glare/cpu/fftw_float_plan: executing an empty plan");
  fftwf_execute(plan_);
}

void FftwFloatPlan::execute(std::complex<float>* in, std::complex<float>* out) const {
  if (plan_ == nullptr) throw std::logic_error("glare/cpu/fftw_float_plan: executing an empty plan");
  fftwf_execute_dft(plan_, reinterpret_cast<fftwf_complex*>(in), reinterpret_cast<fftwf_complex*>(out));
}

void FftwFloatPlan::execute(float* in, std::complex<float>* out) const {
  if (plan_ == nullptr) throw std::logic_error("glare/cpu/fftw_float_plan: executing an empty plan");
  fftwf_execute_dft_r2c(plan_, in, reinterpret_cast<fftwf_complex*>(out));
}

FftwFloatPlan FftwFloatPlan::real_row_forward(int length, float* in, std::complex<float>* out, FftwPlanning planning) {
  return FftwFloatPlan(plan_with_threads(1, "a float real row FFT", planning, [&](unsigned flags) {
    return fftwf_plan_dft_r2c_1d(length, in, reinterpret_cast<fftwf_complex*>(out), flags | FFTW_PRESERVE_INPUT);
  }));
}

void FftwFloatPlan::execute(std::complex<float>* in, float* out) const {
  if (plan_ == nullptr) throw std::logic_error("glare/cpu/fftw_float_plan: executing an empty plan");
  fftwf_execute_dft_c2r(plan_, reinterpret_cast<fftwf_complex*>(in), out);
}

FftwFloatPlan FftwFloatPlan::real_row_inverse(int length, std::complex<float>* in, float* out, FftwPlanning planning) {
  return FftwFloatPlan(plan_with_threads(1, "an inverse float real row FFT", planning, [&](unsigned flags) {
    return fftwf_plan_dft_c2r_1d(length, reinterpret_cast<fftwf_complex*>(in), out, flags);
  }));
}

FftwFloatPlan FftwFloatPlan::complex_row_forward(int length, std::complex<float>* in, std::complex<float>* out) {
  const bool rows_keep_alignment = (static_cast<std::size_t>(length) * sizeof(std::complex<float>)) % 64 == 0;
  return FftwFloatPlan(plan_with_threads(1, "a float complex row FFT", FftwPlanning::estimate, [&](unsigned flags) {
    return fftwf_plan_dft_1d(length, reinterpret_cast<fftwf_complex*>(in), reinterpret_cast<fftwf_complex*>(out),
                             FFTW_FORWARD, flags | (rows_keep_alignment ? 0 : FFTW_UNALIGNED));
  }));
}

FftwFloatPlan FftwFloatPlan::complex_forward(int rows, int cols, std::complex<float>* in, std::complex<float>* out,
                                             int threads, FftwPlanning planning) {
  return FftwFloatPlan(plan_with_threads(threads, "a float complex 2D FFT", planning, [&](unsigned flags) {
    return fftwf_plan_dft_2d(rows, cols, reinterpret_cast<fftwf_complex*>(in), reinterpret_cast<fftwf_complex*>(out),
                             FFTW_FORWARD, flags);
  }));
}

FftwFloatPlan FftwFloatPlan::real_forward(int rows, int cols, int count, float* in, std::complex<float>* out, int threads,
                                          FftwPlanning planning) {
  return FftwFloatPlan(plan_with_threads(threads, "float real 2D FFTs", planning, [&](unsigned flags) {
    const int size[2] = {rows, cols};
    return fftwf_plan_many_dft_r2c(2, size, count, in, nullptr, 1, rows * cols, reinterpret_cast<fftwf_complex*>(out),
                                   nullptr, 1, rows * (cols / 2 + 1), flags | FFTW_PRESERVE_INPUT);
  }));
}

FftwFloatPlan FftwFloatPlan::real_inverse(int rows, int cols, int count, std::complex<float>* in, float* out, int threads,
                                          FftwPlanning planning) {
  return FftwFloatPlan(plan_with_threads(threads, "float inverse real 2D FFTs", planning, [&](unsigned flags) {
    const int size[2] = {rows, cols};
    return fftwf_plan_many_dft_c2r(2, size, count, reinterpret_cast<fftwf_complex*>(in), nullptr, 1,
                                   rows * (cols / 2 + 1), out, nullptr, 1, rows * cols, flags);
  }));
}

FftwFloatPlan FftwFloatPlan::real_rows_forward(int rows, int cols, int count, int first_row, int row_count, float* in,
                                               std::complex<float>* out, int threads, FftwPlanning planning) {
  const int spectrum_cols = cols / 2 + 1;
  return FftwFloatPlan(plan_with_threads(threads, "float real row FFTs", planning, [&](unsigned flags) {
    const fftwf_iodim length{cols, 1, 1};
    const fftwf_iodim loops[2] = {{count, rows * cols, rows * spectrum_cols}, {row_count, cols, spectrum_cols}};
    return fftwf_plan_guru_dft_r2c(1, &length, 2, loops, in + static_cast<std::ptrdiff_t>(first_row) * cols,
                                   reinterpret_cast<fftwf_complex*>(out + static_cast<std::ptrdiff_t>(first_row) * spectrum_cols),
                                   flags | FFTW_PRESERVE_INPUT);
  }));
}

FftwFloatPlan FftwFloatPlan::real_rows_inverse(int rows, int cols, int count, int first_row, int row_count,
                                               std::complex<float>* in, float* out, int threads,
                                               FftwPlanning planning) {
  const int spectrum_cols = cols / 2 + 1;
  return FftwFloatPlan(plan_with_threads(threads, "float inverse real row FFTs", planning, [&](unsigned flags) {
    const fftwf_iodim length{cols, 1, 1};
    const fftwf_iodim loops[2] = {{count, rows * spectrum_cols, rows * cols}, {row_count, spectrum_cols, cols}};
    return fftwf_plan_guru_dft_c2r(1, &length, 2, loops,
                                   reinterpret_cast<fftwf_complex*>(in + static_cast<std::ptrdiff_t>(first_row) * spectrum_cols),
                                   out + static_cast<std::ptrdiff_t>(first_row) * cols, flags);
  }));
}

FftwFloatPlan FftwFloatPlan::transposed_columns(int rows, int cols, int count, int sign, std::complex<float>* data,
                                                int threads, FftwPlanning planning) {
  const int spectrum_cols = cols / 2 + 1;
  return FftwFloatPlan(plan_with_threads(threads, "float column FFTs (transposed)", planning, [&](unsigned flags) {
    const fftwf_iodim length{rows, 1, 1};
    const fftwf_iodim loops[1] = {{count * spectrum_cols, rows, rows}};
    return fftwf_plan_guru_dft(1, &length, 1, loops, reinterpret_cast<fftwf_complex*>(data),
                               reinterpret_cast<fftwf_complex*>(data), sign, flags);
  }));
}

FftwFloatPlan FftwFloatPlan::complex_columns(int rows, int cols, int count, int sign, std::complex<float>* in,
                                             std::complex<float>* out, bool preserve_input, int threads,
                                             FftwPlanning planning) {
  const int spectrum_cols = cols / 2 + 1;
  return FftwFloatPlan(plan_with_threads(threads, "float column FFTs", planning, [&](unsigned flags) {
    const fftwf_iodim length{rows, spectrum_cols, spectrum_cols};
    const fftwf_iodim loops[2] = {{count, rows * spectrum_cols, rows * spectrum_cols}, {spectrum_cols, 1, 1}};
    return fftwf_plan_guru_dft(1, &length, 2, loops, reinterpret_cast<fftwf_complex*>(in),
                               reinterpret_cast<fftwf_complex*>(out), sign,
                               flags | (preserve_input ? FFTW_PRESERVE_INPUT : FFTW_DESTROY_INPUT));
  }));
}

}  // namespace glarelab

#pragma once
// FFTW float plans made once and executed every frame, for the planned float32 glare path
// (glare/cpu/float_glare.h) and the FFTW floor it is measured against (glare/cpu/fftw_floor.h).
//
// Planning, with FFTW's own threads (libfftw3f_threads): FFTW_ESTIMATE picks the plan from the sizes,
// strides, alignment and thread count alone, never from timings, so the same input gives the same
// output on every run. FFTW_MEASURE times candidate plans and could pick another one (with other
// rounding) from run to run, unless the plan it picked is kept: `kept` plans are measured once per
// machine and read from the wisdom file ever after (glare/cpu/fftw_wisdom.h), so they too are the same plans
// in every run on that machine. The thread count is part of the plan, so it is fixed
// (kGlareCpuThreads) rather than read from the machine: a session's frames do not depend on the
// number of cores of the computer it runs on.
//
// FFTW's planner is not thread-safe: planning and destroying plans take fftw_planner_mutex() (the
// same mutex glare/cpu/fft.cpp takes); executing a plan does not.
#include <complex>
#include <cstddef>
#include <memory>
#include <mutex>

struct fftwf_plan_s;

namespace glarelab {

// Threads of the planned float32 CPU path: its FFTW plans, the aperture rows, the power spectrum
// and the spectral PSF. Two: the cores of the machines this runs on in the lab.
inline constexpr int kGlareCpuThreads = 2;

std::mutex& fftw_planner_mutex();

// How a plan is chosen. estimate: from the sizes alone (FFTW_ESTIMATE; the glare path, for the
// reason above). measure: the fastest of the candidates FFTW times (FFTW_MEASURE; the FFTW floor,
// which must be the fastest FFTW does the transforms, and FFTW_ESTIMATE's own N x N complex plan is
// far from that: docs/PERFORMANCE.md, "Measurements behind the code's choices"). Measured
// plans leave wisdom that later estimate plans of the same problems would follow; whoever makes
// measured plans calls forget_fftw_float_wisdom() after them, while no other thread plans.
// kept: FFTW_MEASURE with the wisdom kept in a file (glare/cpu/fftw_wisdom.h), or FFTW_ESTIMATE where none can
// be kept. Measured and kept plans overwrite their arrays while they are made: data (zero padding
// included) is written after planning.
enum class FftwPlanning { estimate, measure, kept };

// FFTW float's accumulated wisdom forgotten (fftwf_forget_wisdom), under fftw_planner_mutex().
void forget_fftw_float_wisdom();

// Memory from fftwf_malloc (aligned for FFTW's SIMD codelets), count elements of T, zeroed.
template <typename T>
class FftwFloatBuffer {
 public:
  FftwFloatBuffer() = default;
  explicit FftwFloatBuffer(std::size_t count);
  T* data() { return data_.get(); }
  const T* data() const { return data_.get(); }
  std::size_t size() const { return size_; }
  T& operator[](std::size_t k) { return data_[k]; }
  const T& operator[](std::size_t k) const { return data_[k]; }

 private:
  struct Free {
    void operator()(T* pointer) const;
  };
  std::unique_ptr<T[], Free> data_;
  std::size_t size_ = 0;
};

// A plan that owns its fftwf_plan; move-only.
class FftwFloatPlan {
 public:
  FftwFloatPlan() = default;
  FftwFloatPlan(FftwFloatPlan&& other) noexcept;
  FftwFloatPlan& operator=(FftwFloatPlan&& other) noexcept;
  FftwFloatPlan(const FftwFloatPlan&) = delete;
  FftwFloatPlan& operator=(const FftwFloatPlan&) = delete;
  ~FftwFloatPlan();
  void execute() const;  // on the arrays it was planned with
  // A complex plan run on other arrays of the planned layout (FFTW's new-array execute,
  // fftwf_execute_dft): the rows of complex_row_forward.
  void execute(std::complex<float>* in, std::complex<float>* out) const;

  // A real plan run on other arrays of the planned alignment (FFTW's new-array execute,
  // fftwf_execute_dft_r2c): the rows of real_row_forward.
  void execute(float* in, std::complex<float>* out) const;

  // A complex-to-real plan run on other arrays of the planned alignment (fftwf_execute_dft_c2r): the
  // rows of real_row_inverse.
  void execute(std::complex<float>* in, float* out) const;

  // Forward complex rows x cols DFT (exponent sign -1, unnormalised), out of place.
  static FftwFloatPlan complex_forward(int rows, int cols, std::complex<float>* in, std::complex<float>* out, int threads,
                                       FftwPlanning planning = FftwPlanning::estimate);
  // One forward complex DFT of `length` values, out of place, made to be run by execute(in, out) on
  // any row of two arrays of such rows (each row its own call, so that rows known to be zero are
  // skipped and the rows are shared among threads). Planned FFTW_UNALIGNED unless a row's bytes are
  // a multiple of 64, where every row keeps the alignment of fftwf_malloc's arrays.
  static FftwFloatPlan complex_row_forward(int length, std::complex<float>* in, std::complex<float>* out);
  // One forward real DFT of `length` values into length/2 + 1 complex ones, contiguous, out of
  // place, single-threaded, made to be run by execute(in, out) on rows whose addresses have the
  // planned arrays' alignment (fftwf_malloc's, or a multiple of 64 bytes from it): the callers share
  // the rows among their own threads and keep each row in cache from its copy to its transform.
  static FftwFloatPlan real_row_forward(int length, float* in, std::complex<float>* out,
                                        FftwPlanning planning = FftwPlanning::estimate);
  // Its inverse, length/2 + 1 complex values to `length` reals (unnormalised; destroys its input).
  static FftwFloatPlan real_row_inverse(int length, std::complex<float>* in, float* out,
                                        FftwPlanning planning = FftwPlanning::estimate);
  // `count` real rows x cols arrays, `rows * cols` apart, to `count` spectra of rows x (cols/2 + 1),
  // `rows * (cols/2 + 1)` apart (one plan for the three colour channels). Preserves its input.
  static FftwFloatPlan real_forward(int rows, int cols, int count, float* in, std::complex<float>* out, int threads,
                                    FftwPlanning planning = FftwPlanning::estimate);
  // The inverse (complex to real, unnormalised); destroys its input, as every FFTW c2r may.
  static FftwFloatPlan real_inverse(int rows, int cols, int count, std::complex<float>* in, float* out, int threads,
                                    FftwPlanning planning = FftwPlanning::estimate);

  // The same 2D transforms in two passes of 1D transforms, so that rows known to be zero (input)
  // or not wanted (output) are skipped; the layouts are those of real_forward / real_inverse
  // (count arrays of rows x cols reals, of rows x (cols/2 + 1) complex values).
  // Row pass, real to complex: rows [first_row, first_row + row_count) of each array only.
  static FftwFloatPlan real_rows_forward(int rows, int cols, int count, int first_row, int row_count, float* in,
                                         std::complex<float>* out, int threads,
                                         FftwPlanning planning = FftwPlanning::estimate);
  // Row pass, complex to real (destroys its input): rows [first_row, first_row + row_count) only.
  static FftwFloatPlan real_rows_inverse(int rows, int cols, int count, int first_row, int row_count,
                                         std::complex<float>* in, float* out, int threads,
                                         FftwPlanning planning = FftwPlanning::estimate);
  // The column pass of spectra stored transposed, column by column: value (row r, frequency k) of
  // array c at (c (cols/2 + 1) + k) rows + r. The row passes then write and read a column's values
  // together (glare/cpu/float_convolution.h) and the column pass runs over contiguous columns, which FFTW
  // does faster than strided ones (docs/PERFORMANCE.md, "Measurements behind the code's
  // choices").
  // In place, sign FFTW_FORWARD (-1) or FFTW_BACKWARD (+1), over the count (cols/2 + 1) columns
  // laid out as above.
  static FftwFloatPlan transposed_columns(int rows, int cols, int count, int sign, std::complex<float>* data,
                                          int threads, FftwPlanning planning = FftwPlanning::estimate);
  // Column pass over all rows x (cols/2 + 1) complex values, sign FFTW_FORWARD (-1) or
  // FFTW_BACKWARD (+1), out of place; preserve_input keeps `in` (its zero rows) intact.
  static FftwFloatPlan complex_columns(int rows, int cols, int count, int sign, std::complex<float>* in,
                                       std::complex<float>* out, bool preserve_input, int threads,
                                       FftwPlanning planning = FftwPlanning::estimate);

 private:
  explicit FftwFloatPlan(fftwf_plan_s* plan) : plan_(plan) {}
  fftwf_plan_s* plan_ = nullptr;
};

}  // namespace glarelab

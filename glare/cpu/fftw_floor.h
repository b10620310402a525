#pragma once
// The FFTW floor of one dynamic glare frame: the transforms no CPU frame can do without,
// in FFTW float with plans made once (FFTW_MEASURE: the fastest plans FFTW finds, not the
// FFTW_ESTIMATE plans of the glare path) and the threads of the planned float path:
//   - one N x N complex FFT (the aperture to the PSF, Ritschel et al. 2009, Eq. 3);
//   - nine padded real transforms for the RGB convolution: 3 forward (image), 3 forward (PSF),
//     3 inverse, each rows x cols.
// `glarelab bench` times a whole frame against it in the same run; the ratio is the frame's
// overhead over pure FFT work.
#include <complex>
#include <cstddef>

#include "glare/cpu/fftw_double_plan.h"
#include "glare/cpu/fftw_float_plan.h"

namespace glarelab {

class FftwFloatFloor {
 public:
  // psf_grid_px: N; rows x cols: the padded convolution size (glare/cpu/convolution.h). Planning times
  // the candidates (about a second for N = 1024), then forgets FFTW's wisdom: no other thread may
  // make FFTW float plans meanwhile.
  FftwFloatFloor(int psf_grid_px, int rows, int cols, int threads = kGlareCpuThreads);
  void run();  // the ten transforms, one after the other

 private:
  FftwFloatBuffer<std::complex<float>> field_, field_spectrum_;
  FftwFloatBuffer<float> real_in_, real_out_;
  FftwFloatBuffer<std::complex<float>> image_spectrum_, psf_spectrum_;
  FftwFloatPlan psf_fft_;
  FftwFloatPlan forward_[6];
  FftwFloatPlan inverse_[3];
};

// The floor of an RGB convolution over the whole display (the analytic glare, docs/PERFORMANCE.md):
// 3 forward and 3 inverse real 2D transforms of rows x cols, planned once.
class FftwRgbConvolutionFloor {
 public:
  FftwRgbConvolutionFloor(int rows, int cols, int threads = kGlareCpuThreads);
  double run_s();  // the six transforms once, seconds

 private:
  std::size_t real_size_;
  FftwFloatBuffer<float> real_;
  FftwFloatBuffer<std::complex<float>> spectrum_;
  FftwFloatPlan forward_, inverse_;
};

// The floor of a PSF with the observer's refraction (glare/cpu/planned_chromatic_psf.h): one N x N
// complex float64 FFT per wavelength, here the fastest plan FFTW measures on one thread, timed once
// and divided by the threads the PSF's transforms share (a perfect split: the floor, not a plan the
// path could run); the caller multiplies by the wavelengths.
class FftwComplexFloor {
 public:
  explicit FftwComplexFloor(int grid_px, int threads = kGlareCpuThreads);
  double run_s();  // one transform, seconds

 private:
  int threads_ = 1;
  FftwFloatBuffer<std::complex<double>> field_, spectrum_;
  FftwDoublePlan fft_;
};

}  // namespace glarelab

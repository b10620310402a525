#pragma once
// Speed against error of the glare stages on both backends (`glarelab bench`), after Ritschel et al.
// 2009, Table 2: per grid size N, the time of each stage (aperture, FFT + PSF, spectral, convolution
// of an N x 3N/4 HDR frame) on the CPU (FFTW double and float) and GL paths, beside two errors:
//   - arithmetic: relative L2 against the CPU double path at the same N (same aperture, same
//     options), which isolates float and GPU rounding;
//   - discretisation: relative L2 of the monochromatic PSF against the CPU double PSF of the 2N
//     grid over the same aperture width (same degrees per pixel, twice the field), cropped to the
//     central N x N: what the N grid loses to aperture sampling and to the periodic wrap.
// The aperture is the eye model's (EyeModel, default parameters) at a fixed time and seed.
#include <functional>
#include <string>
#include <vector>

#include "core/gl/gl_context.h"

namespace glarelab {

struct GlareBenchmarkOptions {
  std::vector<int> grid_sizes = {256, 512, 1024};
  // The OpenGL context for the gl rows (runner/display/compute_context.h); empty: CPU rows only.
  GlContextFactory gl_context;
  int wavelength_samples = 32;
  int repeats = 1;  // each stage timed this many times; the fastest is kept
  double time_s = 1.0;
  unsigned long long seed = 1;
  std::function<void(const std::string&)> progress;  // one line per step (the command prints it on stderr)
};

struct GlareBenchmarkRow {
  int grid_px = 0;
  std::string backend;  // "cpu float64", "cpu float32", "gl"
  double aperture_s = 0.0;
  double psf_s = 0.0;          // FFT + |F|^2 + normalisation, without the aperture
  double spectral_s = 0.0;     // chromatic blur from the reference PSF
  double convolution_s = 0.0;  // N x 3N/4 RGB frame with the spectral PSF at N/4 display pixels
  double psf_error = 0.0;          // vs CPU double, same N (0 for CPU double itself)
  double spectral_error = 0.0;     // vs CPU double, same N
  double frame_error = 0.0;        // convolved frame vs CPU double pipeline, same N
  double discretisation_error = 0.0;  // monochromatic PSF vs CPU double at 2N, central crop
  double total_s() const { return aperture_s + psf_s + spectral_s + convolution_s; }
};

struct GlareBenchmarkResult {
  std::vector<GlareBenchmarkRow> rows;
  std::string aperture;  // what was diffracted: pupil, primitive counts
  std::string renderer;  // GL_RENDERER, empty without GL
};

// Throws std::invalid_argument for grid sizes the GL FFT cannot take (when gl_context is given) or odd sizes.
GlareBenchmarkResult run_glare_benchmark(const GlareBenchmarkOptions& options);

// A Markdown table, one row per grid and backend, times in ms, errors in scientific notation.
std::string format_glare_benchmark_table(const GlareBenchmarkResult& result);

}  // namespace glarelab

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
//
// Beside the stages, the whole dynamic frame of the planned float32 CPU path (cpu_float_*.h:
// aperture, PSF, spectral PSF at the display scale, RGB convolution) against the FFTW floor
// (glare/cpu/fftw_floor.h: one N x N complex FFT and nine padded real transforms, FFTW float, plans made once,
// the same threads), measured in the same run. Every timed frame takes the eye at a new
// time (1/60 s apart, blinks skipped), so nothing computed for one frame's PSF can serve the next.
// Two frames: a new scene (the image's R, G, B transformed too) and a static scene (its spectrum
// kept from the trial's first frame).
#include <functional>
#include <string>
#include <vector>

#include "core/gl/gl_context.h"
#include "glare/refraction/dioptric_power.h"
#include "glare/glare_backend_kind.h"

namespace glarelab {

struct GlareBenchmarkOptions {
  std::vector<int> grid_sizes = {256, 512, 1024};
  // The OpenGL context for the gl rows (runner/display/compute_context.h); empty: CPU rows only.
  GlContextFactory gl_context;
  int wavelength_samples = 32;
  int repeats = 1;  // each stage timed this many times; the fastest is kept
  int frames = 5;   // whole frames timed per N and scene kind (each at a new eye time), fastest kept
  double time_s = 1.0;
  unsigned long long seed = 1;
  // The observer's residual refraction error (dioptres, observer frame; glare/refraction/dioptric_power.h) put
  // into every eye-model geometry (ApertureGeometry::refraction_error): every path then times and
  // checks the phase of the whole power error, defocus plus refraction, as a session computes it.
  // Zero: the eye model's defocus alone.
  DioptricPower refraction_error;
  std::function<void(const std::string&)> progress;  // one line per step (the command prints it on stderr)
};

struct GlareBenchmarkRow {
  int grid_px = 0;
  GlareBackendKind backend = GlareBackendKind::cpu_float64;  // the table prints its words
  double aperture_s = 0.0;
  double psf_s = 0.0;          // FFT + |F|^2 + normalisation, without the aperture
  double spectral_s = 0.0;     // chromatic blur from the reference PSF
  double convolution_s = 0.0;  // N x 3N/4 RGB frame with the spectral PSF at N/4 display pixels
  // gl only: the convolution's GPU time alone (timestamp queries from the image's upload to the
  // result's read-back), without the host's checks and bright-pixel split that convolution_s adds.
  double convolution_gpu_s = 0.0;
  std::string convolution_gpu_stages;  // GL: the fastest call's GPU time by stage (GlConvolutionReport)
  // GL, a static scene under dynamic glare: the image's spectrum kept, a new PSF transformed.
  double static_convolution_s = 0.0, static_convolution_gpu_s = 0.0;
  std::string static_convolution_gpu_stages;
  double psf_error = 0.0;          // vs CPU double, same N (0 for CPU double itself)
  double spectral_error = 0.0;     // vs CPU double, same N
  double frame_error = 0.0;        // convolved frame vs CPU double pipeline, same N
  double discretisation_error = 0.0;  // monochromatic PSF vs CPU double at 2N, central crop
  double total_s() const { return aperture_s + psf_s + spectral_s + convolution_s; }
};

// The whole dynamic frame of the planned float32 CPU path against the FFTW floor, one per N.
struct GlareFrameRow {
  int grid_px = 0;
  int fft_rows = 0, fft_cols = 0;  // the padded convolution size (N x 3N/4 frame, N/4 PSF)
  int threads = 0;
  int frames = 0;                  // timed frames, each at a new eye time; the fastest is kept
  double floor_s = 0.0;            // FFTW float: 1 N x N complex + 9 padded real transforms
  double new_scene_s = 0.0;        // aperture, PSF, spectral, 3 + 3 forward and 3 inverse transforms
  double static_scene_s = 0.0;     // the same with the scene's spectrum kept (3 forward fewer)
  double frame_error = 0.0;        // vs the CPU double pipeline, same N and eye time
  double discretisation_error = 0.0;  // its monochromatic PSF vs CPU double at 2N
  double new_scene_ratio() const { return floor_s > 0.0 ? new_scene_s / floor_s : 0.0; }
  double static_scene_ratio() const { return floor_s > 0.0 ? static_scene_s / floor_s : 0.0; }
};

struct GlareBenchmarkResult {
  std::vector<GlareBenchmarkRow> rows;
  std::vector<GlareFrameRow> frames;  // one per N
  std::string aperture;  // what was diffracted: pupil, primitive counts
  std::string renderer;  // GL_RENDERER, empty without GL
};

// Throws std::invalid_argument for grid sizes the GL FFT cannot take (when gl_context is given) or odd sizes.
GlareBenchmarkResult run_glare_benchmark(const GlareBenchmarkOptions& options);

// A Markdown table, one row per grid and backend, times in ms, errors in scientific notation.
std::string format_glare_benchmark_table(const GlareBenchmarkResult& result);

// A Markdown table of the GL frame per N (empty without gl rows): the PSF stages, the convolution's
// GPU time and wall time, and the frame both ways, in ms to three significant digits.
std::string format_gl_frame_table(const GlareBenchmarkResult& result);

// A Markdown table of the whole frames against the FFTW floor, one row per N: times in ms, ratios.
std::string format_glare_frame_table(const GlareBenchmarkResult& result);

}  // namespace glarelab

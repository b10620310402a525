#pragma once
// Speed against error of the analytic glare (`glarelab bench`; Spencer 1995's model and CIE 146): a
// full-screen HDR frame (default 1920 x 1080, a dim room with lamps) convolved with the analytic
// PSF over the whole display on the planned float32 path, beside
//   - the FFTW floor of the same size in the same run: the 3 forward and 3 inverse real 2D
//     transforms of the padded frame (plans made once, the same threads), which any FFT
//     convolution of an RGB frame must do;
//   - its error against the float64 convolution with the same kernel (max over pixels of
//     |float32 - float64| / the frame's largest glared value, and relative L2);
//   - the one-off cost of integrating the kernel over the display's pixels, and the memory of the
//     kept spectra;
// and the hybrid eye's and the default (human) eye's frames against the plain Ritschel frame on the same display (dynamic eye,
// each frame at a new time), through the glare stage a session uses; and the Ritschel frame with
// the observer's refraction (a residual of -1 / -1 x 45 D: the PSF one FFT per wavelength with the
// eye's LCA on the CPU in float64), dynamic (a PSF every frame) and static (the PSF once per
// condition, then the convolution alone).
#include <functional>
#include <string>
#include <vector>

namespace glarelab {

struct AnalyticBenchmarkOptions {
  int width_px = 1920, height_px = 1080;
  double viewing_distance_mm = 600.0, pixel_pitch_mm = 0.25;
  int frames = 5;              // timed frames, the fastest kept
  int ritschel_grid_px = 256;  // the wave-optics grid of the hybrid comparison
  std::function<void(const std::string&)> progress;
};

struct AnalyticBenchmarkRow {
  std::string model;         // "spencer mesopic", "spencer adaptive", "cie"
  double kernel_build_s = 0.0;
  double frame_s = 0.0;      // fastest frame
  double floor_s = 0.0;      // FFTW floor, same size and threads
  double max_error = 0.0;    // max |f32 - f64| / max(f64)
  double l2_error = 0.0;     // relative L2
  double memory_mib = 0.0;   // spectra kept
  int fft_cols = 0, fft_rows = 0;
};

struct AnalyticBenchmarkResult {
  int width_px = 0, height_px = 0, threads = 0;
  std::vector<AnalyticBenchmarkRow> rows;
  double ritschel_frame_s = 0.0;  // plain Ritschel dynamic frame through the glare stage
  double hybrid_frame_s = 0.0;    // hybrid (Spencer far field) dynamic frame
  double hybrid_setup_s = 0.0;    // the hybrid's far kernel, once per session
  double human_frame_s = 0.0;     // the default eye ("human": calibrated near field, CIE far field), one
                                  // composed frame again and again as in a dynamic interval (far glare kept)
  double human_new_frame_s = 0.0; // the same with a different composed frame every time (far glare computed)
  double human_setup_s = 0.0;     // its far kernel and near rings, once per session
  double stage_floor_s = 0.0;     // FFTW floor of a frame of an interval (3 forward + 3 inverse)
  int stage_fft_cols = 0, stage_fft_rows = 0;  // its padded size: the frame grown by the display PSF
  double human_max_error = 0.0;   // the default eye's frame against the float64 backend's: max / peak
  double human_l2_error = 0.0;    // and relative L2
  int wavelength_samples = 0;     // of the stage's spectral PSFs
  double refraction_dynamic_frame_s = 0.0;  // Ritschel dynamic frame with a refraction
  double refraction_static_first_s = 0.0;   // static: the first frame (PSF and convolution)
  double refraction_static_frame_s = 0.0;   // static: a later frame (the PSF kept)
};

AnalyticBenchmarkResult run_analytic_benchmark(const AnalyticBenchmarkOptions& options);
std::string format_analytic_benchmark(const AnalyticBenchmarkResult& result);

}  // namespace glarelab

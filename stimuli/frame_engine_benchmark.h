#pragma once
// One eye's whole frame through each frame engine (stimuli/frame_engine.h) for `glarelab bench`: the
// perception stages' test frame (stimuli/perception/stage_timing.h) with static Ritschel glare
// (N = 256, 16 wavelengths) between adaptation and acuity and every stage on, the scene's facts
// kept from frame to frame as a session keeps them (FrameFacts), the CPU engine
// (the glare on the planned float32 path) beside the GL engine (the GL glare backend and the GL
// stages, the frame kept on the GPU and only the first read back), each frame's error against the reference (the CPU
// engine with the float64 glare, `[glare] backend = "cpu"`) by max_relative_pixel_error at the
// chain's floor, 1e-4 of the display peak (the worst pixel), and as a relative L2 norm (the pixels
// weighed by their light). Beside each frame, the FFTW floor measured in the same run
// (glare/cpu/fftw_floor.h, as the other glare rows): the transforms no CPU frame can do without, 3
// forward and 3 inverse real 2D transforms of each lit box's padded convolution (the glare's
// input changes with the eye's adaptation every frame; the static PSF's spectrum could be kept), in
// FFTW float with plans made once and the planned path's threads. The stages' and the glare's own
// rows, with their floors, are printed beside it by the bench.
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/gl/gl_context.h"
#include "glare/analytic/analytic_psf.h"

namespace glarelab {

struct FrameEngineBenchmarkOptions {
  int width_px = 1920, height_px = 1080;
  int repeats = 3;  // frames after the first (plans, buffers and the PSF made); the fastest kept
  // The glare: the wave-optics eye alone (these rows' own), or another wave-optics model (hybrid,
  // human) whose frame the floor's transforms, the wave-optics part's, are then a part of.
  GlareModel model = GlareModel::ritschel;
  bool refraction_rows = true;  // false: the PSF with a refraction is not timed
  GlContextFactory gl_context;  // empty: the CPU engine only
  std::function<void(const std::string&)> progress;
};

struct FrameEngineBenchmarkRow {
  std::string engine;       // "cpu" or "gl"
  std::string reason;       // the engine's reason sentence
  double first_frame_s = 0.0;
  double fastest_frame_s = 0.0;
  double max_relative_error = 0.0;  // against the reference frame, per pixel at the floor
  double relative_l2_error = 0.0;   // against the reference frame, over all pixels
  double floor_s = 0.0;             // the FFTW floor, measured right after this engine's frames
  // The GL engine, its frames kept on the GPU: the fastest frame's GPU time by stage (EyeFrame::
  // gpu_stages_s) and what it read back (core/gl/read_back.h); empty for the CPU engine.
  std::vector<std::pair<std::string, double>> gpu_stages_s;
  std::string read_backs_per_frame;
  double ratio() const { return floor_s > 0.0 ? fastest_frame_s / floor_s : 0.0; }
};

// The display PSF of the static eye with the observer's refraction (-1 D, N = 256, 16 wavelengths:
// one FFT per wavelength with the eye's LCA), what a frame of a condition with a refraction adds to
// the glare: the reference (cpu float64) and the CPU engine's (the planned path, its transforms in
// float64), the fastest of the repeats, beside its FFTW floor (16 N x N complex float64 transforms,
// one measured plan on one thread divided by the path's threads) and its largest difference from the
// reference PSF over the reference's peak.
struct RefractionPsfBenchmarkRow {
  std::string backend;  // the glare backend's kind
  double psf_s = 0.0;
  double floor_s = 0.0;
  double max_error_over_peak = 0.0;
  double ratio() const { return floor_s > 0.0 ? psf_s / floor_s : 0.0; }
};

struct FrameEngineBenchmarkResult {
  int width_px = 0, height_px = 0;
  std::string model;  // the glare model's name
  double floor_cd_m2 = 0.0;
  double reference_s = 0.0;  // the reference frame's time
  // The convolutions the floor transforms: one padded size (rows x cols) per lit box.
  std::vector<std::pair<int, int>> floor_sizes;
  std::vector<FrameEngineBenchmarkRow> rows;
  std::vector<RefractionPsfBenchmarkRow> refraction_rows;  // the reference first
};

FrameEngineBenchmarkResult run_frame_engine_benchmark(const FrameEngineBenchmarkOptions& options);
// A Markdown table: engine, first frame ms, fastest ms, floor ms, ratio, error against the reference.
std::string format_frame_engine_benchmark(const FrameEngineBenchmarkResult& result);
// A GL row's fastest frame by stage: "adaptation 2.75 ms, glare 5.66 ms, ...; read back: ..." (empty
// for a row without GPU stages).
std::string describe_gpu_stages(const FrameEngineBenchmarkRow& row);

}  // namespace glarelab

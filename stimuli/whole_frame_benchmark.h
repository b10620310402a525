#pragma once
// One eye's whole 1920 x 1080 frame on the CPU engine for `glarelab bench` (issue 32's whole-frame
// goal): the perception rows' frame (stimuli/perception/stage_timing.h) with the depth bench's
// depths (stimuli/depth_of_field_benchmark.h, resampled to the frame) through the depth of field,
// then the default eye's glare (GlareModel::human: the calibrated wave-optics near field and the CIE
// far field, dynamic eye) between adaptation and acuity and every perception stage
// (stimuli/frame_engine.h, the CPU engine), each frame anew (the depth of field's buffers kept from
// frame to frame, DepthOfFieldBuffers, as the engine keeps its own). Beside it, the sum of its floors,
// each passed once after each frame and the fastest pass kept:
//   - the glare: the FFTW floor of a frame of an interval, 3 forward and 3 inverse real transforms
//     of the frame padded by the display PSF (glare/cpu/fftw_floor.h; as the glare model rows);
//   - the depth of field: streaming its bytes once (core/streaming_floor.h: the frame's 16 bytes and
//     the depth's 4 read, 16 written a pixel); it is no one transform (each depth layer is blurred
//     directly or by FFT, stimuli/depth_of_field_blur.h), so this floor is what no form of it can
//     beat, not what its convolutions need;
//   - each per-pixel perception stage's streaming floor (16 bytes a pixel read for the adaptation,
//     16 read and 16 written for acuity, tone mapping and scotopic colour; as the CPU stage rows).
// Each part's time (wall clock and the process' CPU time) is printed too, to say where a frame's
// time goes. The error: the frame against the same frame with the glare on the float64 reference
// backend (the CPU engine with [glare] backend = "cpu"), relative L2 and the largest per-pixel
// error at 1e-4 of the display peak (the perception rows' metric); the float32 stages' own error
// against their float64 forms is in the CPU stage rows.
#include <string>
#include <utility>
#include <vector>

namespace glarelab {

struct WholeFrameBenchmarkOptions {
  int width_px = 1920, height_px = 1080;
  int repeats = 3;  // frames after the first; the fastest kept
  int threads = 2;  // the depth of field's and the floors' (the engine's stages take the machine's)
};

struct WholeFramePart {
  std::string name;
  double wall_s = 0.0, cpu_s = 0.0;              // the part's time in the fastest frame's run
  double floor_wall_s = 0.0, floor_cpu_s = 0.0;  // its floor, the fastest of the floor's passes
};

struct WholeFrameBenchmarkResult {
  int width_px = 0, height_px = 0;
  int fft_rows = 0, fft_cols = 0;     // the glare floor's padded size
  int depth_layers = 0;               // of the depth of field
  double first_frame_s = 0.0;
  double frame_wall_s = 0.0, frame_cpu_s = 0.0;  // the fastest frame: wall clock, and its CPU time
  std::vector<WholeFramePart> parts;             // depth of field; glare and perception stages (the engine)
  double floor_wall_s = 0.0, floor_cpu_s = 0.0;  // the sums of the floors
  std::vector<std::pair<std::string, double>> floor_parts_cpu_s;  // each floor's CPU time
  double relative_l2_error = 0.0, max_relative_error = 0.0;
  double ratio_wall() const { return floor_wall_s > 0.0 ? frame_wall_s / floor_wall_s : 0.0; }
  double ratio_cpu() const { return floor_cpu_s > 0.0 ? frame_cpu_s / floor_cpu_s : 0.0; }
};

WholeFrameBenchmarkResult run_whole_frame_benchmark(const WholeFrameBenchmarkOptions& options);
std::string format_whole_frame_benchmark(const WholeFrameBenchmarkResult& result);

}  // namespace glarelab

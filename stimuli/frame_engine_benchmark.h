#pragma once
// One eye's whole frame through each frame engine (stimuli/frame_engine.h) for `glarelab bench`: the
// perception stages' test frame (stimuli/perception/stage_timing.h) with static Ritschel glare
// (N = 256, 16 wavelengths) between adaptation and acuity and every stage on, the CPU engine
// (the glare on the planned float32 path) beside the GL engine (the GL glare backend and the GL
// stages, the frame uploaded and read back), each frame's error against the reference (the CPU
// engine with the float64 glare, `[glare] backend = "cpu"`) by max_relative_pixel_error at the
// chain's floor, 1e-4 of the display peak (the worst pixel), and as a relative L2 norm (the pixels
// weighed by their light). The stages' and the
// glare's own rows, with their floors, are printed beside it by the bench.
#include <functional>
#include <string>
#include <vector>

#include "core/gl/gl_context.h"

namespace glarelab {

struct FrameEngineBenchmarkOptions {
  int width_px = 1920, height_px = 1080;
  int repeats = 3;  // frames after the first (plans, buffers and the PSF made); the fastest kept
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
};

struct FrameEngineBenchmarkResult {
  int width_px = 0, height_px = 0;
  double floor_cd_m2 = 0.0;
  double reference_s = 0.0;  // the reference frame's time
  std::vector<FrameEngineBenchmarkRow> rows;
};

FrameEngineBenchmarkResult run_frame_engine_benchmark(const FrameEngineBenchmarkOptions& options);
// A Markdown table: engine, first frame ms, fastest ms, error against the reference.
std::string format_frame_engine_benchmark(const FrameEngineBenchmarkResult& result);

}  // namespace glarelab

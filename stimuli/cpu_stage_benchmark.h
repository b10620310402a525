#pragma once
// The CPU engine's per-pixel stages at their floor, for `glarelab bench` and
// bench/perception_bench.cpp: each float32 stage that sessions run (the perception stages of
// stimuli/perception/perception_stages_float.h, the spectacle warp of stimuli/spectacle_warp.h) timed
// on a 1920 x 1080 frame beside its floor, each run of the stage followed at once by a run of its
// floor (core/streaming_floor.h: the bytes the stage must read and write once, with the same
// threads), and its error against the float64 reference by stage_timing.h's pixel metric. The
// perception stages run on the perception rows' frame (perception_test_frame: 0.001 to 1e4 cd/m2, a
// dark half that the acuity stage blurs); the warp on the same frame through a -6.00 DS lens, 30.7
// deg across.
// Floors: adaptation reads the frame (16 bytes a pixel); acuity, tone mapping, scotopic colour and
// the warp read and write it (32); the chain of all four perception stages is timed from the
// scene to the display frame (its copy of the scene included) against the sum of their floors.
#include <string>
#include <vector>

namespace glarelab {

struct CpuStageBenchmarkOptions {
  int width_px = 1920, height_px = 1080;
  int repeats = 5;   // each stage and floor this many times; the fastest and the median kept
  int threads = 0;   // 0: one per hardware thread (what sessions use)
};

struct CpuStageBenchmarkRow {
  std::string stage;
  double best_s = 0.0, median_s = 0.0;              // the stage
  double floor_best_s = 0.0, floor_median_s = 0.0;  // its floor
  double cpu_best_s = 0.0, floor_cpu_best_s = 0.0;  // process CPU time (all threads), least of the repeats
  double max_relative_error = 0.0;                  // against the float64 reference
  double error_floor = 0.0;                         // the metric's floor, cd/m2
  double thesis_gtx1070_ms = -1.0;                  // Luidolt Table 7.1 per eye, -1 where none
};

struct CpuStageBenchmarkResult {
  int width_px = 0, height_px = 0, threads = 0;
  std::vector<CpuStageBenchmarkRow> rows;
};

// Throws std::invalid_argument for a frame below 16 x 16 or repeats < 1.
CpuStageBenchmarkResult run_cpu_stage_benchmark(const CpuStageBenchmarkOptions& options);
// A Markdown table: stage, best and median ms, floor best and median ms, ratio of the bests, error.
std::string format_cpu_stage_benchmark(const CpuStageBenchmarkResult& result);

}  // namespace glarelab

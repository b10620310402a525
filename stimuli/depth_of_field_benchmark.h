#pragma once
// The depth-of-field stage's benchmark scene and its timed run (`glarelab bench`, and
// bench/depth_of_field_bench.cpp for the Google Benchmark rows): a 1024 x 768 frame with depth, a
// far wall at 4 m over the upper half, a floor running from 4 m at the horizon to 0.45 m at the
// bottom row, and three striped boards in front (0.4 m, 0.6 m, 1.5 m); the eye accommodated at
// 0.6 m with -0.5 D of cylinder at TABO 20, pupil radius 2 mm; the display 1024 x 768 px at
// 0.25 mm pitch seen from 600 mm (0.0239 deg a pixel: 4.8 px of blur per dioptre of error).
//
// For scale, Kakimoto et al. 2007 (section 5; GeForce 7800 GTX, 3.2 GHz Pentium 4, 1024 x 768):
// the blurred image of their Figure 1 (ten-sample blur, no spectacle lens) at about 30 fps (33 ms
// a frame). Their blur draws the scene's geometry ten times with displaced vertices; this stage
// blurs an image with depth on the CPU.
#include <string>
#include <vector>

#include "core/image.h"
#include "stimuli/depth_of_field.h"
#include "stimuli/depth_of_field_reference.h"

namespace glarelab {

inline constexpr int kDepthBenchWidthPx = 1024;
inline constexpr int kDepthBenchHeightPx = 768;

struct DepthBenchScene {
  ImageRGBA image;
  std::vector<float> depth_m;
};
const DepthBenchScene& depth_of_field_bench_scene();
DepthOfFieldSettings depth_of_field_bench_settings(int threads);

struct DepthOfFieldBenchmarkResult {
  int threads = 0;
  double tolerance_px = 0.0;
  DepthOfFieldReport report;
  double fastest_ms = 0.0;       // wall clock, the fastest of the repeats
  double reference_s = 0.0;      // the per-pixel reference's time (once)
  DepthOfFieldError error;       // the layered stage against the per-pixel reference
};
// The stage on the bench scene `repeats` times (the fastest kept), and its error against the
// per-pixel reference (stimuli/depth_of_field_reference.h).
DepthOfFieldBenchmarkResult run_depth_of_field_benchmark(int threads, int repeats);
std::string format_depth_of_field_benchmark(const DepthOfFieldBenchmarkResult& result);

}  // namespace glarelab

#pragma once
// Speed against error of the two convolutions of the analytic glare (glare/analytic/analytic_glare.h) on a
// full-screen HDR frame (default 1920 x 1080: a dim room of 0.5-2 cd/m2 with five lamps of
// 2e3-2e4 cd/m2 and a 400 cd/m2 window), per model (Spencer mesopic, Spencer adaptive at
// 1 cd/m2, CIE), in one run:
//   - the full path (an FFT of twice the frame) and the FFTW floor of its padded size (3 forward
//     and 3 inverse real 2D transforms, planned once, the same threads): under load the ratio
//     frame / floor is what holds;
//   - the two-level path (glare/analytic/analytic_two_level.h) with the given split;
//   - both against the float64 full convolution with the same kernel: max |error| / the frame's
//     largest glared value and relative L2 over the frame, and the max |error| / peak near the
//     bright sources (within near_sources_deg of a pixel over 100 cd/m2, where the halo lies) and
//     away from them, where also max |error| / the local value is given (the dim room's own
//     glare, which a 10-bit display at the peak's scale would not show anyway).
// The floor, the full and the two-level frames are timed in turn, `frames` times, the fastest of
// each kept.
#include <functional>
#include <string>
#include <vector>

#include "core/image.h"
#include "glare/analytic/analytic_two_level.h"

namespace glarelab {

struct TwoLevelBenchmarkOptions {
  int width_px = 1920, height_px = 1080;
  double viewing_distance_mm = 600.0, pixel_pitch_mm = 0.25;
  int frames = 5;
  TwoLevelSplit split;
  double near_sources_deg = 4.0;  // beyond Spencer's halo ring (3 lambda / 568 degrees, Eq. 7)
  std::function<void(const std::string&)> progress;
};

struct FrameErrors {
  double max = 0.0;           // max |error| / max(reference), whole frame
  double l2 = 0.0;            // relative L2, whole frame
  double near_max = 0.0;      // max |error| / max(reference), near the bright sources
  double far_max = 0.0;       // max |error| / max(reference), away from them
  double far_relative = 0.0;  // max |error| / |reference| at the pixel, away from them
};

struct TwoLevelBenchmarkRow {
  std::string model;            // "spencer mesopic", "spencer adaptive (at 1 cd/m2)", "cie"
  double full_frame_s = 0.0;    // fastest full-path frame
  double floor_s = 0.0;         // FFTW floor of the full path's size, same run
  double two_level_frame_s = 0.0;
  FrameErrors full, two_level;  // against float64
  int full_fft_cols = 0, full_fft_rows = 0;
  int near_fft_cols = 0, near_fft_rows = 0, far_fft_cols = 0, far_fft_rows = 0;
  double full_memory_mib = 0.0, two_level_memory_mib = 0.0;
};

struct TwoLevelBenchmarkResult {
  int width_px = 0, height_px = 0, threads = 0;
  TwoLevelSplit split;
  std::vector<TwoLevelBenchmarkRow> rows;
};

// The bench's frame (also what `glarelab bench` convolves).
ImageRGBA analytic_benchmark_frame(int width_px, int height_px);
// Errors of `fast` against `exact`; `near` marks the pixels near bright sources (width x height).
FrameErrors frame_errors(const ImageRGBA& fast, const ImageRGBA& exact, const std::vector<bool>& near);
// Pixels within radius_px (Chebyshev) of a pixel whose R, G or B exceeds threshold.
std::vector<bool> near_bright_pixels(const ImageRGBA& frame, float threshold, int radius_px);

TwoLevelBenchmarkResult run_two_level_benchmark(const TwoLevelBenchmarkOptions& options);
std::string format_two_level_benchmark(const TwoLevelBenchmarkResult& result);

}  // namespace glarelab

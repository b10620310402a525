#pragma once
// Speed and agreement of the perception stages (Luidolt 2020, chapters 5 and 6) on the CPU double
// reference and the GL path, at a given frame size, for `glarelab bench` and the benchmarks: each
// stage on the same input on both paths (so each is compared alone), then the whole chain in
// Fig. 6.1's order, beside the thesis' own GPU figures (section 7.5, Table 7.1: GeForce GTX 1070,
// 1440 x 1600 per eye: adaptation 0.18 ms, acuity 0.36 ms, scotopic 0.14 ms).
//
// The input is perception_test_frame: luminances from 0.001 to 1e4 cd/m2 (a logarithmic ramp
// across the width with texture), colour patches with saturated colours, a 1e3 cd/m2 rectangle
// with sharp edges in the dark part, and a 1e4 cd/m2 source there too.
//
// Agreement (docs/PERCEPTION.md): for images, the largest over pixels of
//   max_c |gl_c - cpu_c| / max(max_c |cpu_c|, floor)
// (relative to the pixel's largest channel), with floor = 1e-6 cd/m2 for scene-referred outputs
// (acuity) and 1e-4 of the display peak for display-referred ones (tone mapping, scotopic, the
// chain); for the adaptation luminance |gl - cpu| / cpu.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/display_spec.h"
#include "core/gl/gl_context.h"
#include "core/image.h"

namespace glarelab {

struct PerceptionTimingOptions {
  int width_px = 1920, height_px = 1080;
  double viewing_distance_mm = 600.0, pixel_pitch_mm = 0.25;  // 41.9 px/deg at the centre
  double peak_luminance_cd_m2 = 250.0;
  // The OpenGL context for the GL rows (runner/display/compute_context.h); empty: CPU only.
  GlContextFactory gl_context;
  int repeats = 3;  // each stage timed this many times on each path; the fastest is kept
  std::function<void(const std::string&)> progress;  // one line per stage (a command prints it on stderr)
};

struct PerceptionTimingRow {
  std::string stage;           // "adaptation", "acuity", "tone_mapping aces_narkowicz", ..., "all stages"
  double cpu_s = 0.0;          // fastest CPU double time
  double gl_s = 0.0;           // fastest GL time (glFinish included; buffers already on the GPU,
                               // except "all stages": upload and read-back included); 0 without GL
  double max_relative_error = 0.0;  // GL against CPU, the metric above; 0 without GL
  double floor = 0.0;          // the metric's floor in the output's cd/m2 (0 for the scalar)
  double thesis_gtx1070_ms = -1.0;  // Table 7.1 per eye, -1 where the thesis gives none
};

struct PerceptionTimingResult {
  int width_px = 0, height_px = 0;
  double pixels_per_degree = 0.0;
  double adapted_luminance_cd_m2 = 0.0;  // the frame's (CPU), which tone mapping and scotopic use
  std::string renderer;                  // GL_RENDERER and platform, empty without GL
  std::vector<PerceptionTimingRow> rows;
};

// Throws std::invalid_argument for a size below 16 x 16 or above 8192, or repeats < 1; DisplayError
// when the GL context cannot be made.
PerceptionTimingResult time_perception_stages(const PerceptionTimingOptions& options);

// The display these rows, the frame engine's and the whole frame's assume: `options`' viewing
// distance, pixel pitch (41.9 px/deg at the centre by default) and peak luminance at its size.
DisplaySpec perception_timing_display(const PerceptionTimingOptions& options);
// The same at width_px x height_px with the options' defaults.
DisplaySpec perception_timing_display(int width_px, int height_px);
// A Markdown table: stage, CPU ms, GL ms, thesis GTX 1070 ms, max relative error, floor.
std::string format_perception_timing(const PerceptionTimingResult& result);

// The input frame described above, linear Rec.709 in cd/m2, alpha 1; deterministic in the seed.
ImageRGBA perception_test_frame(int width_px, int height_px, std::uint64_t seed = 1);
// ||actual - expected|| / ||expected|| over the R, G and B of every pixel (alpha left out): the
// whole-frame error the frame engine's rows report.
double relative_l2_rgb(const ImageRGBA& actual, const ImageRGBA& expected);
// The image metric described above; throws std::invalid_argument for images of different sizes.
double max_relative_pixel_error(const ImageRGBA& actual, const ImageRGBA& expected, double floor);

}  // namespace glarelab

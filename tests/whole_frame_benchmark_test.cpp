// The whole-frame row of `glarelab bench` (stimuli/whole_frame_benchmark.h) on a small frame: the
// frame's glare convolved (a skipped glare is refused), the depth of field in more than one layer,
// the glare's floor transforming the frame padded by the PSF the glare stage makes (to the next
// 2,3,5-smooth length), each part's floor measured, and the frame within the planned float32
// glare's error of the same frame with the float64 glare.
#include <gtest/gtest.h>

#include <string>

#include "core/fft_size.h"
#include "stimuli/glare_stage.h"
#include "stimuli/whole_frame_benchmark.h"

namespace glarelab {
namespace {

TEST(WholeFrameBenchmark, TheFrameBesideItsFloorsAndItsError) {
  WholeFrameBenchmarkOptions options;
  options.width_px = 160;
  options.height_px = 120;
  options.repeats = 1;
  const WholeFrameBenchmarkResult result = run_whole_frame_benchmark(options);
  EXPECT_GT(result.depth_layers, 1);
  ASSERT_EQ(result.parts.size(), 2u);
  EXPECT_EQ(result.parts[0].name, "depth of field");
  double floor_cpu_s = 0.0;
  for (const WholeFramePart& part : result.parts) {
    EXPECT_GT(part.cpu_s, 0.0) << part.name;
    EXPECT_GT(part.floor_cpu_s, 0.0) << part.name;
    floor_cpu_s += part.floor_cpu_s;
  }
  EXPECT_DOUBLE_EQ(result.floor_cpu_s, floor_cpu_s);
  EXPECT_DOUBLE_EQ(result.ratio_cpu(), result.frame_cpu_s / result.floor_cpu_s);
  ASSERT_EQ(result.floor_parts_cpu_s.size(), 4u);

  // The padded size of the default eye's convolution, from the PSF its glare stage makes.
  DisplaySpec display;
  display.width_px = options.width_px;
  display.height_px = options.height_px;
  display.viewing_distance_mm = 600.0;
  display.pixel_pitch_mm = 0.25;
  display.peak_luminance_cd_m2 = 250.0;
  GlareSpec spec;
  spec.wavelength_samples = 16;
  GlareStage stage(spec, display, 1);
  const int psf_px = stage.display_psf(GlareMode::static_eye, 1.0, 100.0)->size_px;
  EXPECT_EQ(result.fft_rows, smooth_fft_size(options.height_px + psf_px - 1));
  EXPECT_EQ(result.fft_cols, smooth_fft_size(options.width_px + psf_px - 1));

  // The planned float32 glare against the float64 one, through every perception stage.
  EXPECT_GT(result.relative_l2_error, 0.0);
  EXPECT_LT(result.relative_l2_error, 1e-4);
  EXPECT_NE(format_whole_frame_benchmark(result).find("| whole frame |"), std::string::npos);
}

}  // namespace
}  // namespace glarelab

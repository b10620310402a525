// The frame engine rows of `glarelab bench` (stimuli/frame_engine_benchmark.h) on a small frame:
// each row carries the FFTW floor measured in the same run beside its time and its error against the
// float64 reference frame; the floor transforms the padded size of the convolution the engine's glare
// really does (the frame is lit everywhere: one box, the whole frame, grown by the PSF the glare
// stage makes, to the next 2,3,5-smooth length); the table prints the floor and the ratio; the PSF
// with a refraction by the CPU engine within 1e-5 of the float64 reference's, beside its floor; the
// hybrid eye's frame (the GPU target rows') within 1e-4 of its float64 reference.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/fft_size.h"
#include "stimuli/frame_engine.h"
#include "stimuli/frame_engine_benchmark.h"

namespace glarelab {
namespace {

TEST(FrameEngineBenchmark, TheHybridEyesFrameAgreesWithItsFloat64ReferenceAndOtherModelsAreRefused) {
  // The GPU target rows' glare (the hybrid eye: Ritschel near, Spencer far) through the CPU engine:
  // its planned float32 frame against the float64 one, every perception stage, on a small frame.
  FrameEngineBenchmarkOptions options;
  options.width_px = 160;
  options.height_px = 120;
  options.repeats = 1;
  options.model = GlareModel::hybrid;
  options.refraction_rows = false;
  const FrameEngineBenchmarkResult result = run_frame_engine_benchmark(options);
  EXPECT_EQ(result.model, "hybrid");
  ASSERT_EQ(result.rows.size(), 1u);
  EXPECT_GT(result.rows.front().relative_l2_error, 0.0);
  EXPECT_LT(result.rows.front().relative_l2_error, 1e-4);
  EXPECT_TRUE(result.refraction_rows.empty());
  EXPECT_NE(format_frame_engine_benchmark(result).find("glare hybrid"), std::string::npos);
  options.model = GlareModel::spencer;
  EXPECT_THROW(run_frame_engine_benchmark(options), std::invalid_argument);
}

TEST(FrameEngineBenchmark, AGlRowsStagesAreNamedInTheirOrderInMilliseconds) {
  FrameEngineBenchmarkRow row;
  EXPECT_EQ(describe_gpu_stages(row), "");  // a CPU row has no GPU stages
  row.gpu_stages_s = {{"adaptation", 2.75e-3}, {"glare", 5.664e-3}, {"convolution crop", 3e-5}};
  row.read_backs_per_frame = "0 frame, 1 kernel (786.4 kB)";
  EXPECT_EQ(describe_gpu_stages(row),
            "adaptation 2.75 ms, glare 5.66 ms, convolution crop 0.03 ms; read back: 0 frame, 1 kernel (786.4 kB)");
}

TEST(FrameEngineBenchmark, EachRowCarriesTheFftwFloorOfItsConvolutionAndItsError) {
  FrameEngineBenchmarkOptions options;
  options.width_px = 160;
  options.height_px = 120;
  options.repeats = 1;
  const FrameEngineBenchmarkResult result = run_frame_engine_benchmark(options);
  ASSERT_EQ(result.rows.size(), 1u);  // no GL context: the CPU engine alone
  const FrameEngineBenchmarkRow& row = result.rows.front();
  EXPECT_EQ(row.engine, "cpu");
  EXPECT_GT(row.floor_s, 0.0);
  EXPECT_GT(row.fastest_frame_s, 0.0);
  EXPECT_DOUBLE_EQ(row.ratio(), row.fastest_frame_s / row.floor_s);
  // The planned float32 glare against the float64 one, through every perception stage.
  EXPECT_GT(row.relative_l2_error, 0.0);
  EXPECT_LT(row.relative_l2_error, 1e-4);

  // The PSF the bench's glare stage makes (its display, N = 256), and the one padded convolution.
  DisplaySpec display;
  display.width_px = options.width_px;
  display.height_px = options.height_px;
  display.viewing_distance_mm = 600.0;
  display.pixel_pitch_mm = 0.25;
  display.peak_luminance_cd_m2 = 250.0;
  GlareSpec spec;
  spec.model = GlareModel::ritschel;
  spec.grid_px = 256;
  spec.wavelength_samples = 16;
  GlareStage stage(spec, display, 1);
  const int psf_px = stage.display_psf(GlareMode::static_eye, 1.0, 100.0)->size_px;
  const std::vector<std::pair<int, int>> expected = {
      {smooth_fft_size(options.height_px + psf_px - 1), smooth_fft_size(options.width_px + psf_px - 1)}};
  EXPECT_EQ(result.floor_sizes, expected);

  // The PSF with a refraction: the reference, then the CPU engine's float32 one within 1e-5 of its
  // peak, each beside its floor.
  ASSERT_EQ(result.refraction_rows.size(), 2u);
  EXPECT_EQ(result.refraction_rows[0].backend, "cpu float64");
  EXPECT_EQ(result.refraction_rows[1].backend, "cpu float32 planned");
  EXPECT_GT(result.refraction_rows[1].max_error_over_peak, 0.0);
  EXPECT_LT(result.refraction_rows[1].max_error_over_peak, 1e-5);
  for (const RefractionPsfBenchmarkRow& refraction : result.refraction_rows) {
    EXPECT_GT(refraction.floor_s, 0.0);
    EXPECT_DOUBLE_EQ(refraction.ratio(), refraction.psf_s / refraction.floor_s);
  }

  const std::string table = format_frame_engine_benchmark(result);
  EXPECT_NE(table.find("| glare backend | PSF ms | FFTW floor ms | ratio | max error / peak |"), std::string::npos);
  EXPECT_NE(table.find("| FFTW floor ms | ratio |"), std::string::npos) << table;
  const std::string size = std::to_string(expected.front().second) + " x " + std::to_string(expected.front().first);
  EXPECT_NE(table.find("(" + size + ")"), std::string::npos) << table;
}

}  // namespace
}  // namespace glarelab

// The CPU stage rows of `glarelab bench` (stimuli/cpu_stage_benchmark.h) on a small frame: every
// float32 stage sessions run, each with its floor timed beside it, and each within the issue's
// 1e-5 of its float64 reference by the perception rows' metric.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "stimuli/cpu_stage_benchmark.h"

namespace glarelab {
namespace {

TEST(CpuStageBenchmark, EveryStageBesideItsFloorAndWithinItsErrorOfTheReference) {
  CpuStageBenchmarkOptions options;
  options.width_px = 96;
  options.height_px = 64;
  options.repeats = 3;
  options.threads = 2;
  const CpuStageBenchmarkResult result = run_cpu_stage_benchmark(options);
  EXPECT_EQ(result.width_px, 96);
  EXPECT_EQ(result.height_px, 64);
  EXPECT_EQ(result.threads, 2);
  const std::vector<std::string> stages{"adaptation", "acuity", "tone_mapping", "scotopic", "all perception stages",
                                        "spectacle warp -6.00 DS", "spectacle warp -6.00 DS, grids traced each frame"};
  ASSERT_EQ(result.rows.size(), stages.size());
  for (std::size_t i = 0; i < stages.size(); ++i) {
    const CpuStageBenchmarkRow& row = result.rows[i];
    EXPECT_EQ(row.stage.rfind(stages[i], 0), 0u) << row.stage;
    EXPECT_GT(row.best_s, 0.0) << row.stage;
    EXPECT_LE(row.best_s, row.median_s) << row.stage;
    EXPECT_GT(row.floor_best_s, 0.0) << row.stage;
    EXPECT_LE(row.floor_best_s, row.floor_median_s) << row.stage;
    EXPECT_GE(row.max_relative_error, 0.0) << row.stage;
    EXPECT_LT(row.max_relative_error, 1e-5) << row.stage;
  }
  const std::string table = format_cpu_stage_benchmark(result);
  EXPECT_NE(table.find("| spectacle warp -6.00 DS |"), std::string::npos);
  EXPECT_NE(table.find("96 x 64, 2 threads"), std::string::npos);
}

TEST(CpuStageBenchmark, RefusesAFrameBelowSixteenPixelsAndNoRepeats) {
  CpuStageBenchmarkOptions small;
  small.width_px = 15;
  EXPECT_THROW(run_cpu_stage_benchmark(small), std::invalid_argument);
  CpuStageBenchmarkOptions none;
  none.repeats = 0;
  EXPECT_THROW(run_cpu_stage_benchmark(none), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab

// glarelab bench --memory-only (runner/cli/bench_memory.h): the rows run their child sessions and
// report a peak resident size that agrees with the one the child read from /proc/self/status; a
// small display keeps it quick (no size or time is asserted: those depend on the machine).
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>

#include "cli_process.h"
#include "runner/cli/bench_memory.h"
#include "runner/session/glared_region.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

TEST(BenchMemory, RowsReportTheChildsPeakResidentSizeAsProcSeesIt) {
  const test::ScratchDir scratch;
  const test::RunOutput run = test::run_glarelab(
      {"bench", "--memory-only", "--memory-size", "256", "144", "--memory-frames", "4"}, scratch.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  // | glare | stimulus frames shown | peak resident (ru_maxrss) | VmHWM | store bound | wall s |
  const std::regex row(R"(\| (control|dynamic) \| ([0-9]+) \| ([0-9]+) MB \| ([0-9]+) MB \| ([^|]+) \| [0-9.]+ \|)");
  int rows = 0;
  for (auto it = std::sregex_iterator(run.output.begin(), run.output.end(), row); it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    SCOPED_TRACE(m.str());
    ++rows;
    EXPECT_EQ(std::stoi(m[2]), 4) << "one trial of 4 stimulus frames";
    const double rss_mb = std::stod(m[3]), hwm_mb = std::stod(m[4]);
    EXPECT_GT(hwm_mb, 1.0);
    // The same high-water mark from two places (wait4's ru_maxrss, /proc's VmHWM read just before
    // the child exits), each rounded to a megabyte.
    EXPECT_LE(std::abs(rss_mb - hwm_mb), 1.0 + 0.02 * hwm_mb);
    if (m[1] == "dynamic") {
      const auto bound = static_cast<double>(prepared_frames_bound_bytes(256, 144, 4));
      EXPECT_EQ(m[5].str(), std::to_string(static_cast<long>(std::round(bound / 1e6))) + " MB");
    } else {
      EXPECT_EQ(m[5].str(), "none");
    }
  }
  EXPECT_EQ(rows, 2) << run.output;
  const cli::SessionMemoryOptions small{.width_px = 256, .height_px = 144, .stimulus_frames = 4};
  EXPECT_NE(run.output.find("256 x 144"), std::string::npos);
  EXPECT_NE(run.output.find(std::to_string(cli::memory_scene_px(small)) + " px square"), std::string::npos);
}

// --grids: the glare rows' grid sizes; a size the GL FFT cannot take is refused naming the flag,
// before any session or transform runs.
TEST(BenchGrids, RefusesSizesTheGlFftCannotTakeNamingTheFlag) {
  const test::ScratchDir scratch;
  for (const char* grid : {"48", "50"}) {
    const test::RunOutput run = test::run_glarelab({"bench", "--grids", "256", grid}, scratch.path());
    EXPECT_EQ(run.exit_code, 2) << run.output;
    EXPECT_NE(run.output.find("--grids"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find(std::string("grid ") + grid), std::string::npos) << run.output;
    EXPECT_EQ(run.output.find("memory:"), std::string::npos) << "refused before the memory rows: " << run.output;
  }
  const test::RunOutput odd = test::run_glarelab({"bench", "--grids", "33", "--no-gl"}, scratch.path());
  EXPECT_EQ(odd.exit_code, 2) << odd.output;
  EXPECT_NE(odd.output.find("odd"), std::string::npos) << odd.output;
}

TEST(BenchMemory, MemoryOnlyExcludesTheOtherSections) {
  const test::ScratchDir scratch;
  const test::RunOutput run = test::run_glarelab({"bench", "--memory-only", "--analytic-only"}, scratch.path());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("--memory-only"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace glarelab

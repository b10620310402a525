// The speed-against-error table of `glarelab bench`, through the library on tiny grids (the command
// itself with --quick takes about 40 s on this machine, too long for the suite).
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "glare/glare_benchmark.h"
#include "runner/display/compute_context.h"

namespace glarelab {
namespace {

TEST(GlareBenchmark, TinyGridsGiveOneRowPerBackendWithErrorsAndATable) {
  GlareBenchmarkOptions options;
  options.grid_sizes = {32, 64};
  options.wavelength_samples = 4;
  options.gl_context = gl::compute_context_factory();
  std::vector<std::string> progress;
  options.progress = [&](const std::string& line) { progress.push_back(line); };
  const GlareBenchmarkResult result = run_glare_benchmark(options);
  ASSERT_EQ(result.rows.size(), 6u);
  EXPECT_EQ(progress.size(), 8u);  // per grid: the 2N reference and three backends
  const char* backends[] = {"cpu float64", "cpu float32", "gl"};
  for (std::size_t k = 0; k < result.rows.size(); ++k) {
    const GlareBenchmarkRow& row = result.rows[k];
    EXPECT_EQ(row.grid_px, k < 3 ? 32 : 64);
    EXPECT_EQ(row.backend, backends[k % 3]);
    EXPECT_GT(row.total_s(), 0.0);
    if (k % 3 == 0) {
      EXPECT_EQ(row.psf_error, 0.0);  // the reference itself
    } else {
      // float32 (CPU or GPU) against double: rounding only, far below the discretisation error.
      EXPECT_GT(row.psf_error, 0.0);
      EXPECT_LT(row.psf_error, 1e-5) << row.backend;
      EXPECT_LT(row.spectral_error, 1e-4) << row.backend;
      EXPECT_LT(row.frame_error, 1e-5) << row.backend;
    }
    // Against the 2N grid: the coarse grid's sampling error, the same for every backend to 1e-4.
    EXPECT_GT(row.discretisation_error, 1e-4);
    EXPECT_NEAR(row.discretisation_error, result.rows[k / 3 * 3].discretisation_error, 1e-4);
  }
  EXPECT_NE(result.aperture.find("eye model"), std::string::npos);

  const std::string table = format_glare_benchmark_table(result);
  std::istringstream lines(table);
  std::vector<std::string> rows;
  for (std::string line; std::getline(lines, line);) rows.push_back(line);
  ASSERT_EQ(rows.size(), 8u);  // header, rule, six rows
  EXPECT_EQ(rows[0].rfind("| N | backend | aperture ms", 0), 0u) << rows[0];
  EXPECT_EQ(rows[2].rfind("| 32 | cpu float64 |", 0), 0u) << rows[2];
  EXPECT_NE(rows[2].find("0 (reference)"), std::string::npos) << rows[2];
  EXPECT_EQ(rows[7].rfind("| 64 | gl |", 0), 0u) << rows[7];
  for (const std::string& row : rows) EXPECT_EQ(std::count(row.begin(), row.end(), '|'), 12) << row;

  options.grid_sizes = {48};  // not a GL FFT size
  EXPECT_THROW(run_glare_benchmark(options), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab

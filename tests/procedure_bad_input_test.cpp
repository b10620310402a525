// Bad [procedure] sections stop `glarelab run` before anything runs: exit 2, file:line of the
// offending key, and no database.
#include <gtest/gtest.h>

#include "cli_process.h"

namespace glarelab {
namespace {

using test::run_glarelab;
using test::ScratchDir;

// examples/spencer_staircase.toml copied into dir with whole lines starting with a key replaced,
// scene paths made absolute. Returns the path and the 1-based line of the replaced line.
std::pair<std::filesystem::path, int> staircase_variant(const std::filesystem::path& dir, const std::string& key,
                                                        const std::string& replacement) {
  const std::filesystem::path examples = std::filesystem::path(GLARELAB_SOURCE_DIR) / "examples";
  std::istringstream in(test::read_bytes((examples / "spencer_staircase.toml").string()));
  std::ostringstream out;
  std::string line;
  int replaced = -1;
  for (int number = 1; std::getline(in, line); ++number) {
    if (replaced < 0 && line.rfind(key + " ", 0) == 0) {
      line = replacement;
      replaced = number;
    }
    for (const std::string relative : {"\"scenes/", "\"spencer_conditions.csv"}) {
      const auto pos = line.find(relative);
      if (pos != std::string::npos) line.replace(pos, 1, "\"" + examples.string() + "/");
    }
    out << line << "\n";
  }
  const auto path = dir / "staircase.toml";
  test::write_bytes(path.string(), out.str());
  return {path, replaced};
}

void expect_refused(const std::string& key, const std::string& replacement, const std::string& message) {
  const ScratchDir scratch;
  const auto [experiment, line] = staircase_variant(scratch.path(), key, replacement);
  ASSERT_GT(line, 0) << key << " not found in the example";
  const auto db = scratch.path() / "bad.db";
  const auto run = run_glarelab(
      {"run", experiment.string(), "--display", "offscreen", "--observer", "simulated", "--db", db.string()},
      scratch.path());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find(experiment.string() + ":" + std::to_string(line) + ":"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find(message), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(db)) << "nothing may be written before the input is valid";
}

TEST(ProcedureBadInput, UnknownProcedure) {
  expect_refused("type", "type = \"method_of_limits\"", "unsupported procedure 'method_of_limits'");
}

TEST(ProcedureBadInput, UnknownParameter) {
  expect_refused("n_trials", "n_trial = 8", "n_trial");
}

TEST(ProcedureBadInput, StepListLongerThanReversalCount) {
  // Three step sizes need at least three reversals to all be used.
  expect_refused("n_reversals", "n_reversals = 2", "smaller than the 3 step sizes");
}

TEST(ProcedureBadInput, DurationShorterThanOneFrame) {
  // 10 ms at 60 Hz is less than one refresh period (16.7 ms).
  expect_refused("stimulus_duration_s", "stimulus_duration_s = 0.01", "shorter than one frame");
}

}  // namespace
}  // namespace glarelab

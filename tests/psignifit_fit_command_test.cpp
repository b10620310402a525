// `glarelab fit` run as a user would: on one of psignifit 4's reference cases
// (../shared/data/psignifit-cases; skipped, saying so, when absent) its RESULT.json carries
// psignifit's fields and agrees with psignifit's result; bad options are refused with file, line
// and key and exit code 2.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "cli_process.h"
#include "scratch_dir.h"

namespace glarelab::test {
namespace {

using nlohmann::json;

std::filesystem::path cases_dir() {
  if (const char* shared = std::getenv("GLARELAB_SHARED_DIR"); shared != nullptr && *shared != '\0')
    return std::filesystem::path(shared) / "data" / "psignifit-cases";
  return std::filesystem::path(GLARELAB_SOURCE_DIR) / ".." / "shared" / "data" / "psignifit-cases";
}

TEST(FitCommand, WritesPsignifitsFieldsThatAgreeWithPsignifit) {
  const auto dir = cases_dir();
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " is not present (psignifit 4's reference cases, ../shared/data)";
  ScratchDir scratch;
  const auto out = scratch.path() / "result.json";
  const std::string name = "test_2AFC_logistic";
  const RunOutput run = run_glarelab({"fit", (dir / (name + "_data.csv")).string(), "--options", (dir / (name + "_opt.json")).string(),
                                      "--out", out.string()},
                                     scratch.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("threshold"), std::string::npos) << run.output;
  std::ifstream in(out);
  const json result = json::parse(in);
  std::ifstream reference_in(dir / (name + "_res.json"));
  const json reference = json::parse(reference_in);
  const double range = 1.75 - 0.25;  // the case's levels
  for (const char* field : {"Fit", "meanFit"}) {
    ASSERT_EQ(result[field].size(), 5u) << field;
    EXPECT_NEAR(result[field][0].get<double>(), reference[field][0].get<double>(), 0.01 * range) << field;
    EXPECT_NEAR(result[field][1].get<double>(), reference[field][1].get<double>(), 0.01 * range) << field;
    for (int p = 2; p < 5; ++p) EXPECT_NEAR(result[field][p].get<double>(), reference[field][p].get<double>(), 0.01) << field << p;
  }
  ASSERT_EQ(result["conf_Intervals"].size(), 5u);
  for (int level = 0; level < 3; ++level) {
    EXPECT_NEAR(result["conf_Intervals"][0][0][level].get<double>(), reference["conf_Intervals"][0][0][level].get<double>(), 0.02 * range);
    EXPECT_NEAR(result["conf_Intervals"][0][1][level].get<double>(), reference["conf_Intervals"][0][1][level].get<double>(), 0.02 * range);
  }
  EXPECT_NEAR(result["deviance"].get<double>(), reference["deviance"].get<double>(), 0.01 * reference["deviance"].get<double>());
  EXPECT_NEAR(result["logPmax"].get<double>(), reference["logPmax"].get<double>(), 1e-6);
}

TEST(FitCommand, RefusesUnknownOptionsNamingFileLineAndKey) {
  ScratchDir scratch;
  const auto data = scratch.path() / "data.csv";
  std::ofstream(data) << "0.5,3,10\n1.0,6,10\n1.5,9,10\n";
  const auto options = scratch.path() / "opt.json";
  std::ofstream(options) << "{\n  \"expType\": \"2AFC\",\n  \"threshold_pc\": 0.5\n}\n";
  const RunOutput run = run_glarelab({"fit", data.string(), "--options", options.string(), "--out", (scratch.path() / "r.json").string()},
                                     scratch.path());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("opt.json:3:3"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("threshold_pc"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(scratch.path() / "r.json"));

  std::ofstream(data) << "0.5,3,10\n1.0,12,10\n";
  const RunOutput bad_data = run_glarelab({"fit", data.string()}, scratch.path());
  EXPECT_EQ(bad_data.exit_code, 2) << bad_data.output;
  EXPECT_NE(bad_data.output.find("data.csv:2"), std::string::npos) << bad_data.output;
}

}  // namespace
}  // namespace glarelab::test

// Bad input through the command line: exit code 2, a message that says where and what, and
// nothing written to the database.
#include <gtest/gtest.h>

#include "cli_process.h"

namespace glarelab {
namespace {

using test::demo_variant;
using test::run_glarelab;
using test::ScratchDir;

struct BadRun {
  int exit_code;
  std::string output;
  bool database_written;
};

BadRun run_and_validate(const std::filesystem::path& dir, const std::string& experiment) {
  const auto db = dir / "bad.db";
  const auto run = run_glarelab({"run", experiment, "--display", "offscreen", "--observer", "simulated", "--db", db.string()}, dir);
  const auto validate = run_glarelab({"validate", experiment}, dir);
  EXPECT_EQ(validate.exit_code, run.exit_code) << validate.output;
  EXPECT_EQ(validate.output, run.output) << "validate and run must report the same problem";
  return {run.exit_code, run.output, std::filesystem::exists(db)};
}

// The line number of the first line of `path` starting with `prefix` (1-based).
int line_of(const std::filesystem::path& path, const std::string& prefix) {
  std::istringstream in(test::read_bytes(path));
  std::string line;
  for (int number = 1; std::getline(in, line); ++number)
    if (line.rfind(prefix, 0) == 0) return number;
  return -1;
}

TEST(BadInput, UnknownKeyNamesFileLineColumnAndKey) {
  const ScratchDir scratch;
  const auto& dir = scratch.path();
  const auto experiment = demo_variant(dir, {{"stimulus_frames", "stimulus_frame = 30"}});
  const auto bad = run_and_validate(dir, experiment.string());
  EXPECT_EQ(bad.exit_code, 2);
  const std::string where = experiment.string() + ":" + std::to_string(line_of(experiment, "stimulus_frame ")) + ":1:";
  EXPECT_NE(bad.output.find(where), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("stimulus_frame"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("unknown key"), std::string::npos) << bad.output;
  EXPECT_FALSE(bad.database_written);
}

TEST(BadInput, WrongTypeNamesExpectedAndFound) {
  const ScratchDir scratch;
  const auto& dir = scratch.path();
  const auto experiment = demo_variant(dir, {{"stimulus_frames", "stimulus_frames = \"thirty\""}});
  const auto bad = run_and_validate(dir, experiment.string());
  EXPECT_EQ(bad.exit_code, 2);
  const std::string where = experiment.string() + ":" + std::to_string(line_of(experiment, "stimulus_frames ")) + ":";
  EXPECT_NE(bad.output.find(where), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("stimulus_frames"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("integer"), std::string::npos) << bad.output;
  EXPECT_FALSE(bad.database_written);
}

TEST(BadInput, ObserverAgeOutOfRangeNamesFileLineColumnAndKey) {
  const ScratchDir scratch;
  const auto& dir = scratch.path();
  const auto conditions = std::filesystem::path(GLARELAB_SOURCE_DIR) / "examples/demo_conditions.csv";
  const auto experiment =
      demo_variant(dir, {{"file", "file = \"" + conditions.string() + "\"\n\n[observer]\nage_years = 120"}});
  const auto bad = run_and_validate(dir, experiment.string());
  EXPECT_EQ(bad.exit_code, 2);
  const std::string where = experiment.string() + ":" + std::to_string(line_of(experiment, "age_years ")) + ":13: ";
  EXPECT_NE(bad.output.find(where + "key 'observer.age_years': must be from 1 to 100 years, found 120"), std::string::npos)
      << bad.output;
  EXPECT_FALSE(bad.database_written);
}

TEST(BadInput, MissingExperimentFile) {
  const ScratchDir scratch;
  const auto& dir = scratch.path();
  const auto run = run_glarelab({"validate", (dir / "nope.toml").string()}, dir);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.output.find("nope.toml"), std::string::npos) << run.output;
}

TEST(BadInput, MissingCsvColumnNamesTheColumnAndFile) {
  const ScratchDir scratch;
  const auto& dir = scratch.path();
  test::write_bytes(dir / "conditions.csv", "name,scene_a,scene_c\nr1,lamp_100,lamp_200\n");
  const auto experiment = demo_variant(dir, {{"file", "file = \"" + (dir / "conditions.csv").string() + "\""}});
  const auto bad = run_and_validate(dir, experiment.string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find((dir / "conditions.csv").string() + ":1:"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("scene_b"), std::string::npos) << bad.output;
  EXPECT_FALSE(bad.database_written);
}

TEST(BadInput, CorruptExrNamesTheFile) {
  const ScratchDir scratch;
  const auto& dir = scratch.path();
  // A real EXR header followed by garbage: readable magic number, broken content.
  const auto source = std::filesystem::path(GLARELAB_SOURCE_DIR) / "examples/scenes/lamp_200.exr";
  std::string bytes = test::read_bytes(source);
  bytes.resize(bytes.size() / 3);
  test::write_bytes(dir / "lamp_200.exr", bytes);
  const auto experiment = demo_variant(dir, {});
  // Point lamp_200 at the damaged copy.
  std::string text = test::read_bytes(experiment);
  const std::string original = std::filesystem::path(GLARELAB_SOURCE_DIR).string() + "/examples/scenes/lamp_200.exr";
  text.replace(text.find(original), original.size(), (dir / "lamp_200.exr").string());
  test::write_bytes(experiment, text);
  const auto bad = run_and_validate(dir, experiment.string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find((dir / "lamp_200.exr").string()), std::string::npos) << bad.output;
  EXPECT_FALSE(bad.database_written);
}

TEST(BadInput, MissingExrNamesTheFile) {
  const ScratchDir scratch;
  const auto& dir = scratch.path();
  const auto experiment = demo_variant(dir, {});
  std::string text = test::read_bytes(experiment);
  const std::string original = "/examples/scenes/lamp_105.exr";
  text.replace(text.find(original), original.size(), "/examples/scenes/lamp_999.exr");
  test::write_bytes(experiment, text);
  const auto bad = run_and_validate(dir, experiment.string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("lamp_999.exr"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("not found"), std::string::npos) << bad.output;
  EXPECT_FALSE(bad.database_written);
}

TEST(Validate, DemoIsValidAndDescribed) {
  const ScratchDir scratch;
  const auto& dir = scratch.path();
  const auto run = run_glarelab({"validate", std::string(GLARELAB_SOURCE_DIR) + "/examples/demo.toml"}, dir);
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("34 forced_choice trials"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("scene lamp_200: 256x256 px, peak 200 cd/m2"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace glarelab

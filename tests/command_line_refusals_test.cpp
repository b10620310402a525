// Command-line values and files that glarelab refuses before it writes anything: the exit code
// (2 for input, 4 for a database that is not glarelab's), a message that names the option or file
// and the value as typed, and nothing written.
#include <gtest/gtest.h>

#include <sqlite3.h>

#include <filesystem>
#include <string>

#include "cli_process.h"
#include "runner/store/result_store.h"

namespace glarelab {
namespace {

using test::run_glarelab;
using test::ScratchDir;

std::string demo() { return std::string(GLARELAB_SOURCE_DIR) + "/examples/demo.toml"; }

test::RunOutput run_demo(const ScratchDir& scratch, const std::vector<std::string>& extra,
                         const std::filesystem::path& db) {
  std::vector<std::string> arguments = {"run", demo(), "--display", "offscreen", "--observer", "simulated",
                                        "--db", db.string(), "--stop-after", "1"};
  arguments.insert(arguments.end(), extra.begin(), extra.end());
  return run_glarelab(arguments, scratch.path());
}

TEST(CommandLineRefusals, SeedsAreWholeNumbersThatFitTheStoredInteger) {
  const ScratchDir scratch;
  const auto db = scratch.path() / "seeds.db";
  for (const std::string seed : {"-1", "9223372036854775808", "18446744073709551615", "7.5", "1e3", "seven"}) {
    const auto run = run_demo(scratch, {"--seed", seed}, db);
    EXPECT_EQ(run.exit_code, 2) << seed << ": " << run.output;
    EXPECT_NE(run.output.find("--seed: must be a whole number from 0 to 9223372036854775807, found '" + seed + "'"),
              std::string::npos)
        << run.output;
    EXPECT_FALSE(std::filesystem::exists(db)) << seed;
  }
  // The largest seed runs, and is stored as given.
  const auto largest = run_demo(scratch, {"--seed", "9223372036854775807"}, db);
  ASSERT_EQ(largest.exit_code, 0) << largest.output;
  const ResultStore store(db.string());
  EXPECT_EQ(store.load_sessions().at(0).seed, 9223372036854775807u);
}

TEST(CommandLineRefusals, ParticipantNumberMessageStatesItsBounds) {
  const ScratchDir scratch;
  const auto db = scratch.path() / "numbers.db";
  const auto run = run_demo(scratch, {"--participant-number", "0"}, db);
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("--participant-number: must be a whole number from 1 to 1000000, found '0'"),
            std::string::npos)
      << run.output;
  EXPECT_EQ(run.output.find("0.000000"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(db));
}

TEST(CommandLineRefusals, AnotherProgramsDatabaseIsNotTouched) {
  const ScratchDir scratch;
  const auto db = scratch.path() / "other.db";
  sqlite3* other = nullptr;
  ASSERT_EQ(sqlite3_open(db.c_str(), &other), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(other, "CREATE TABLE invoices(id INTEGER, amount REAL); INSERT INTO invoices VALUES(1, 9.5);",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(other);
  const auto before = test::read_bytes(db.string());

  const auto run = run_demo(scratch, {}, db);
  EXPECT_EQ(run.exit_code, 4) << run.output;
  EXPECT_NE(run.output.find(db.string() + ": holds tables but no glarelab schema version: another program's database"),
            std::string::npos)
      << run.output;
  EXPECT_EQ(test::read_bytes(db.string()), before);  // not a byte changed
}

TEST(CommandLineRefusals, ADirectoryAsTheDatabaseIsNamedAsSuch) {
  const ScratchDir scratch;
  const auto run = run_demo(scratch, {}, scratch.path());
  EXPECT_EQ(run.exit_code, 4) << run.output;
  EXPECT_NE(run.output.find(scratch.path().string() + ": is a directory, not a database file"), std::string::npos)
      << run.output;
}

TEST(CommandLineRefusals, AnalyzeReadsADatabaseNamedTwiceOnceAndRefusesAFileAsItsOutput) {
  const ScratchDir scratch;
  const auto db = scratch.path() / "demo.db";
  ASSERT_EQ(run_demo(scratch, {}, db).exit_code, 0);

  const auto once = run_glarelab({"analyze", db.string(), "--out", (scratch.path() / "once").string()}, scratch.path());
  ASSERT_EQ(once.exit_code, 0) << once.output;
  const auto twice = run_glarelab({"analyze", db.string(), (scratch.path() / "." / "demo.db").string(), "--out",
                                   (scratch.path() / "twice").string()},
                                  scratch.path());
  ASSERT_EQ(twice.exit_code, 0) << twice.output;
  EXPECT_NE(twice.output.find("was given more than once; it is read once"), std::string::npos) << twice.output;
  EXPECT_EQ(test::read_bytes((scratch.path() / "twice" / "trials.csv").string()),
            test::read_bytes((scratch.path() / "once" / "trials.csv").string()));

  const auto onto_file = run_glarelab({"analyze", db.string(), "--out", db.string()}, scratch.path());
  EXPECT_EQ(onto_file.exit_code, 2) << onto_file.output;
  EXPECT_NE(onto_file.output.find("--out: " + db.string() + " is a file, not a directory"), std::string::npos)
      << onto_file.output;
}

}  // namespace
}  // namespace glarelab

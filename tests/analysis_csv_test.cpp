// Tidy CSV export: RFC 4180 quoting, exact numbers, condition keys as columns; and the analysis
// of a database written by the demo experiment itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "analysis/tidy_csv.h"
#include "protocols/csv_table.h"
#include "tests/analysis_synthetic.h"
#include "tests/cli_process.h"
#include "tests/scratch_dir.h"

namespace glarelab::analysis {
namespace {

TEST(AnalysisCsv, QuotingNumbersAndColumnNames) {
  EXPECT_EQ(csv_field("plain"), "plain");
  EXPECT_EQ(csv_field("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csv_field("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(csv_field(" padded"), "\" padded\"");
  for (double value : {0.1, 1.0 / 3.0, 1e-300, 123456789.125, -2.5e17}) {
    EXPECT_EQ(std::strtod(csv_number(value).c_str(), nullptr), value) << csv_number(value);
  }
  EXPECT_EQ(csv_number(0.1), "0.1");
  // Python's repr (also shortest round trip) as the reference.
  EXPECT_EQ(csv_number(1.0 / 3.0), "0.3333333333333333");
  EXPECT_EQ(csv_number(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(csv_number(-2.5), "-2.5");
  EXPECT_EQ(condition_column("target cd/m2"), "condition_target_cd_m2");
}

TEST(AnalysisCsv, TrialsCsvFlattensConditionsAndReadsBack) {
  const test::ScratchDir dir;
  const std::string path = dir.file("csv.db");
  {
    ResultStore store(path);
    const auto id = store.begin_session(test::synthetic_session("P,1 \"x\""));
    test::commit_trials(store, id,
                        {{"rating", R"({"name":"a, \"b\"","level":3})", "4", {}, {}, "", {}},
                         {"staircase", R"({"name":"s"})", "left", 1, 0.25, "s", 1}});
    store.finish_session(id, "completed");
  }
  write_tidy_csv(load_databases({path}), dir.path().string());
  // Read back with the project's RFC 4180 reader (protocols/csv_table.h), a second implementation.
  const CsvTable table = parse_csv_text(test::read_bytes(dir.file("trials.csv")), "trials.csv");
  ASSERT_EQ(table.rows.size(), 2u);
  const auto column = [&](const std::string& name) { return static_cast<std::size_t>(table.require_column(name)); };
  EXPECT_EQ(table.rows[0][column("participant")].text, "P,1 \"x\"");
  EXPECT_EQ(table.rows[0][column("condition_name")].text, "a, \"b\"");
  EXPECT_EQ(table.rows[0][column("condition_level")].text, "3");
  EXPECT_EQ(table.rows[0][column("intensity")].text, "");
  EXPECT_EQ(table.rows[1][column("intensity")].text, "0.25");
  EXPECT_EQ(table.rows[1][column("reversal")].text, "1");
  EXPECT_EQ(std::strtod(table.rows[1][column("response_time_s")].text.c_str(), nullptr), 0.4 + 0.01 * 1.0);
}

TEST(AnalysisCsv, DemoExperimentDatabaseAnalyses) {
  const test::ScratchDir dir;
  const std::string db = dir.file("demo.db");
  // The demo experiment with fewer frames per trial and one repetition, to keep the run short.
  const std::string demo =
      test::demo_variant(dir.path(), {{"stimulus_frames", "stimulus_frames = 3"}, {"repetitions", "repetitions = 1"}})
          .string();
  const test::RunOutput run = test::run_glarelab(
      {"run", demo, "--display", "offscreen", "--observer", "simulated", "--participant", "demo", "--db", db}, dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto out = dir.path() / "out";
  const test::RunOutput analyze = test::run_glarelab({"analyze", db, "--out", out.string()}, dir.path());
  ASSERT_EQ(analyze.exit_code, 0) << analyze.output;
  // 17 conditions x 1 repetition x 2 side assignments; the demo crosses luminance ratio with glare
  // mode, so the analysis fits one psychometric function per mode.
  EXPECT_NE(analyze.output.find("Analysed 1 session(s), 34 trial(s)"), std::string::npos) << analyze.output;
  for (const char* mode : {"control", "static", "dynamic"})
    EXPECT_NE(analyze.output.find(std::string("graded choice ") + mode + " (log10 luminance_ratio): PSE "), std::string::npos)
        << analyze.output;
  EXPECT_TRUE(std::filesystem::exists(out / "report.html"));
  const std::string frames = test::read_bytes((out / "frames.csv").string());
  EXPECT_EQ(std::count(frames.begin(), frames.end(), '\n'), 1 + 34 * 3);
}

}  // namespace
}  // namespace glarelab::analysis

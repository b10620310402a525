// The analysis of whole databases: forced-choice pooling, staircases, adjustments, ratings,
// the hard cases (statements, never NaN), HTML escaping, older schemas and the command line.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <regex>
#include <thread>

#include "analysis/analysis_report.h"
#include "analysis/report_output.h"
#include "tests/analysis_synthetic.h"
#include "tests/cli_process.h"
#include "tests/scratch_dir.h"

namespace glarelab::analysis {
namespace {

using test::TrialSpec;

// Participant A: scene Gem 18 of 20 dynamic; Park 12 of 20 dynamic. Participant B: Gem 15/20,
// Park 9/20 (+ 2 'neither' answers in Park).
std::string ritschel_database(const test::ScratchDir& dir) {
  const std::string path = dir.file("preference.db");
  ResultStore store(path);
  struct Block {
    std::string participant, scene;
    int dynamic, total, neither;
  };
  const std::vector<Block> blocks = {{"A", "Gem", 18, 20, 0}, {"A", "Park", 12, 20, 0}, {"B", "Gem", 15, 20, 0},
                                     {"B", "Park", 9, 20, 2}};
  std::map<std::string, std::vector<TrialSpec>> trials;
  for (const Block& block : blocks) {
    for (int i = 0; i < block.total; ++i) {
      trials[block.participant].push_back(
          test::preference_trial(block.scene, "brighter", i % 2 == 0, i < block.dynamic ? "dynamic" : "static"));
    }
    for (int i = 0; i < block.neither; ++i) {
      trials[block.participant].push_back(test::preference_trial(block.scene, "brighter", true, "neither"));
    }
  }
  for (const auto& [participant, specs] : trials) {
    const auto id = store.begin_session(test::synthetic_session(participant));
    test::commit_trials(store, id, specs);
    store.finish_session(id, "completed");
  }
  return path;
}

TEST(AnalysisReport, ForcedChoicePerSceneAndPooledAsRitschel) {
  const test::ScratchDir dir;
  const AnalysisReport report = analyse(load_databases({ritschel_database(dir)}), {});
  const ForcedChoiceAnalysis& fc = report.forced_choice;
  ASSERT_EQ(fc.groups.size(), 2u);
  EXPECT_EQ(fc.groups[0].group, "scene=Gem, instruction=brighter");
  EXPECT_EQ(fc.groups[0].option_a, "dynamic");
  EXPECT_EQ(fc.groups[0].chose_a, 33);
  EXPECT_EQ(fc.groups[0].chose_b, 7);
  EXPECT_EQ(fc.groups[1].chose_a, 21);  // Park: 21 dynamic, 19 static, 2 neither
  EXPECT_EQ(fc.groups[1].neither, 2);
  EXPECT_NEAR(fc.groups[1].neither_share(), 2.0 / 42.0, 1e-15);
  ASSERT_EQ(fc.pooled.size(), 1u);
  const PairPreference& pooled = fc.pooled[0];
  EXPECT_EQ(pooled.group, "pooled: instruction=brighter");
  EXPECT_EQ(pooled.chose_a, 54);
  EXPECT_EQ(pooled.chose_b, 26);
  // Pearson chi2 against no preference with two categories: (a - b)^2 / (a + b) = 28^2 / 80.
  EXPECT_NEAR(pooled.chi_square.statistic, 784.0 / 80.0, 1e-12);
  EXPECT_NEAR(pooled.chi_square.p_value, std::erfc(std::sqrt(784.0 / 160.0)), 1e-14);
  EXPECT_NEAR(pooled.share_a(), 54.0 / 80.0, 1e-15);
}

// Ritschel's own design: the same scene on both sides, each under its own glare mode
// ("left_glare"/"right_glare"), and a sequential (two-interval) block answering "first"/"second".
TEST(AnalysisReport, ForcedChoiceComparesGlareModesOfTheSameSceneAndIntervals) {
  const test::ScratchDir dir;
  const std::string path = dir.file("modes.db");
  {
    ResultStore store(path);
    const auto id = store.begin_session(test::synthetic_session("P1"));
    std::vector<TrialSpec> specs;
    // 10 trials dynamic vs static, sides alternating; dynamic chosen 8 times.
    for (int i = 0; i < 10; ++i) {
      const bool dynamic_left = i % 2 == 0;
      const bool chose_dynamic = i < 8;
      const std::string condition =
          std::string("{\"scene\":\"Gem\",\"instruction\":\"brighter\",\"left\":\"gem\",\"right\":\"gem\",") +
          "\"left_glare\":\"" + (dynamic_left ? "dynamic" : "static") + "\",\"right_glare\":\"" +
          (dynamic_left ? "static" : "dynamic") + "\"}";
      specs.push_back({"forced_choice", condition, (chose_dynamic == dynamic_left) ? "left" : "right", {}, {}, "", {}});
    }
    // 6 sequential trials control (first) vs static (second); static chosen 5 times.
    for (int i = 0; i < 6; ++i) {
      const std::string condition =
          "{\"scene\":\"Park\",\"instruction\":\"realistic\",\"first\":\"park\",\"second\":\"park\","
          "\"first_glare\":\"control\",\"second_glare\":\"static\"}";
      specs.push_back({"forced_choice", condition, i < 5 ? "second" : "first", {}, {}, "", {}});
    }
    test::commit_trials(store, id, specs);
    store.finish_session(id, "completed");
  }
  const ForcedChoiceAnalysis fc = analyse(load_databases({path}), {}).forced_choice;
  EXPECT_TRUE(fc.notes.empty()) << fc.notes.front();
  ASSERT_EQ(fc.groups.size(), 2u);
  EXPECT_EQ(fc.groups[0].option_a, "dynamic");
  EXPECT_EQ(fc.groups[0].option_b, "static");
  EXPECT_EQ(fc.groups[0].chose_a, 8);
  EXPECT_EQ(fc.groups[0].chose_b, 2);
  // Exact two-sided binomial, 8 of 10: 2 * (1 + 10 + 45) / 1024.
  EXPECT_NEAR(fc.groups[0].binomial.p_value, 112.0 / 1024.0, 1e-14);
  EXPECT_EQ(fc.groups[1].option_a, "static");
  EXPECT_EQ(fc.groups[1].option_b, "control");
  EXPECT_EQ(fc.groups[1].chose_a, 5);
  EXPECT_EQ(fc.groups[1].chose_b, 1);
}

// One participant with a staircase that never reverses, one whose answers are all correct, an
// aborted session, adjustments by a single participant (no ANOVA) and ratings.
std::string hard_cases_database(const test::ScratchDir& dir, const std::string& participant) {
  const std::string path = dir.file("hard.db");
  ResultStore store(path);
  const auto id = store.begin_session(test::synthetic_session(participant));
  std::vector<TrialSpec> specs;
  for (int i = 0; i < 20; ++i) {  // descending, never reversed
    specs.push_back({"staircase", "{\"name\":\"falling\"}", "left", 1, 1.0 - 0.04 * i, "falling", 0});
  }
  for (int i = 0; i < 40; ++i) {  // every answer correct at two levels
    specs.push_back({"staircase", "{\"name\":\"perfect\"}", "left", 1, i % 2 == 0 ? 0.5 : 0.6, "perfect", i % 2});
  }
  const char* glare[] = {"control", "static", "dynamic"};
  for (int g = 0; g < 3; ++g) {
    for (int r = 0; r < 2; ++r) {
      specs.push_back({"adjustment", std::string("{\"glare\":\"") + glare[g] + "\",\"target_cd_m2\":\"100\"}", "", {},
                       100.0 + 10.0 * g + r, "", {}});
    }
  }
  for (int i = 0; i < 9; ++i) specs.push_back({"rating", "{\"name\":\"realism\"}", std::to_string(1 + i % 3), {}, {}, "", {}});
  test::commit_trials(store, id, specs);
  store.finish_session(id, "aborted");
  return path;
}

TEST(AnalysisReport, HardCasesGiveStatementsNeverNaN) {
  const test::ScratchDir dir;
  AnalysisOptions options;
  options.bootstrap_samples = 20;
  const AnalysisReport report = analyse(load_databases({hard_cases_database(dir, "P1")}), options);
  ASSERT_EQ(report.staircases.size(), 2u);
  EXPECT_FALSE(report.staircases[0].reversal_threshold.has_value());
  EXPECT_EQ(report.staircases[0].threshold_note, "staircase never reversed: no reversal threshold (20 trials)");
  EXPECT_EQ(report.staircases[1].fits[0].unavailable, "slope not identifiable: all 40 responses correct");
  // The 20 trials flagged as reversals are all at 0.6, so the mean of the last 6 is 0.6.
  ASSERT_TRUE(report.staircases[1].reversal_threshold.has_value());
  EXPECT_EQ(report.staircases[1].reversals, 20);
  EXPECT_NEAR(*report.staircases[1].reversal_threshold, 0.6, 1e-12);

  ASSERT_EQ(report.adjustments.anovas.size(), 1u);
  EXPECT_NE(report.adjustments.anovas[0].anova.unavailable.find("at least 2 participants"), std::string::npos);
  ASSERT_EQ(report.adjustments.cells.size(), 3u);
  EXPECT_NEAR(report.adjustments.cells[2].perceived.mean, 120.5, 1e-12);
  EXPECT_FALSE(report.adjustments.cells[2].perceived.standard_error.has_value());

  ASSERT_EQ(report.ratings.conditions.size(), 1u);
  EXPECT_EQ(report.ratings.conditions[0].categories.size(), 3u);
  EXPECT_NEAR(*report.ratings.conditions[0].mean, 2.0, 1e-15);
  EXPECT_NEAR(*report.ratings.conditions[0].median, 2.0, 1e-15);

  const std::string html = render_html(report);
  EXPECT_NE(html.find("slope not identifiable: all 40 responses correct"), std::string::npos);
  EXPECT_NE(html.find("staircase never reversed"), std::string::npos);
  EXPECT_NE(html.find("was aborted after"), std::string::npos);
  // printf writes non-finite doubles as nan/inf: none may appear as a number or a coordinate.
  const std::regex non_finite(R"([^A-Za-z](nan|NaN|inf|Inf)[^A-Za-z])");
  EXPECT_FALSE(std::regex_search(html, non_finite));
  for (const Figure& figure : report.figures) EXPECT_FALSE(std::regex_search(figure.svg, non_finite)) << figure.file_stem;
}

TEST(AnalysisReport, DatabaseTextIsEscapedInHtmlAndSvg) {
  const test::ScratchDir dir;
  const std::string hostile = "<script>alert(1)</script> & \"quoted\" 'single'";
  AnalysisOptions options;
  options.bootstrap_samples = 0;
  const AnalysisReport report = analyse(load_databases({hard_cases_database(dir, hostile)}), options);
  const std::string html = render_html(report);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("\"quoted\""), std::string::npos);
  EXPECT_NE(html.find("&lt;script&gt;alert(1)&lt;/script&gt; &amp; &quot;quoted&quot; &#39;single&#39;"),
            std::string::npos);
  for (const Figure& figure : report.figures) EXPECT_EQ(figure.svg.find("<script"), std::string::npos);
}

TEST(AnalysisReport, OlderSchemaLoadsWithANote) {
  // A database of schema version 0: the DESIGN contract columns only, written by hand.
  const test::ScratchDir dir;
  const std::string path = dir.file("old.db");
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  const char* sql = R"(
CREATE TABLE sessions(id INTEGER PRIMARY KEY, experiment TEXT, participant TEXT, seed INTEGER, started_utc TEXT,
  finished_utc TEXT, status TEXT, config TEXT, software_version TEXT, renderer TEXT);
CREATE TABLE trials(id INTEGER PRIMARY KEY, session_id INTEGER, trial_index INTEGER, block INTEGER, procedure TEXT,
  condition TEXT, intensity REAL, response TEXT, correct INTEGER, response_time_s REAL, onset_s REAL, staircase TEXT,
  reversal INTEGER);
INSERT INTO sessions VALUES(1, 'old', 'P9', 3, '2020-01-01T00:00:00Z', NULL, 'completed', '', '0.0', 'gl');
INSERT INTO trials VALUES(1, 1, 0, 0, 'rating', '{"name":"x"}', NULL, '4', NULL, 0.5, 1.0, NULL, NULL);
INSERT INTO trials VALUES(2, 1, 1, 0, 'rating', 'not json', NULL, '5', NULL, 0.6, 3.0, NULL, NULL);
)";
  ASSERT_EQ(sqlite3_exec(db, sql, nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(db);
  const LoadedData data = load_databases({path});
  ASSERT_EQ(data.sessions.size(), 1u);
  EXPECT_EQ(data.sessions[0].trials.size(), 2u);
  EXPECT_EQ(data.sessions[0].record.display_backend, "");
  bool schema_note = false;
  bool json_note = false;
  for (const std::string& note : data.notes) {
    schema_note = schema_note || note.find("schema version 0 is older") != std::string::npos;
    json_note = json_note || note.find("not a JSON object") != std::string::npos;
  }
  EXPECT_TRUE(schema_note);
  EXPECT_TRUE(json_note);
  // The file was not migrated by reading it.
  sqlite3_open(path.c_str(), &db);
  sqlite3_stmt* stmt = nullptr;
  sqlite3_prepare_v2(db, "PRAGMA user_version", -1, &stmt, nullptr);
  ASSERT_EQ(sqlite3_step(stmt), SQLITE_ROW);
  EXPECT_EQ(sqlite3_column_int(stmt, 0), 0);
  sqlite3_finalize(stmt);
  sqlite3_close(db);
}

TEST(AnalysisReport, RefusesNewerSchemaAndNonDatabases) {
  const test::ScratchDir dir;
  const std::string path = dir.file("new.db");
  { ResultStore store(path); }
  sqlite3* db = nullptr;
  sqlite3_open(path.c_str(), &db);
  sqlite3_exec(db, "PRAGMA user_version = 99", nullptr, nullptr, nullptr);
  sqlite3_close(db);
  EXPECT_THROW(load_databases({path}), StoreError);
  EXPECT_THROW(load_databases({dir.write("text.db", "hello")}), StoreError);
  EXPECT_THROW(load_databases({dir.file("missing.db")}), StoreError);
}

// A database whose lock another connection holds for a moment (here 300 ms, the whole file: a
// connection in exclusive locking mode inside a write) is read once the lock is released, as the
// store's own writes wait; before, the analysis failed at once with "database is locked".
TEST(AnalysisReport, ADatabaseLockedForAMomentIsReadOnceTheLockIsReleased) {
  const test::ScratchDir dir;
  const std::string path = ritschel_database(dir);
  sqlite3* holder = nullptr;
  ASSERT_EQ(sqlite3_open_v2(path.c_str(), &holder, SQLITE_OPEN_READWRITE, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(holder, "PRAGMA locking_mode=EXCLUSIVE; BEGIN EXCLUSIVE; UPDATE sessions SET config = config;",
                         nullptr, nullptr, nullptr),
            SQLITE_OK)
      << sqlite3_errmsg(holder);
  const auto locked_at = std::chrono::steady_clock::now();
  std::thread release([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    sqlite3_exec(holder, "COMMIT", nullptr, nullptr, nullptr);
    sqlite3_close(holder);  // ends the exclusive locking mode's hold on the file
  });
  LoadedData data;
  EXPECT_NO_THROW(data = load_databases({path}));
  const double waited_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - locked_at).count();
  release.join();
  EXPECT_EQ(data.sessions.size(), 2u);
  // The read came after the release: the lock was held for 300 ms from before the clock started.
  EXPECT_GE(waited_s, 0.3);
}

// Found by scripts/sanitize.sh (LeakSanitizer): refusing a file that is not a database left the
// PRAGMA statement unfinalized, so sqlite3_close failed and the connection (100 kB) leaked on
// every refused file. SQLite's own count of the memory it holds must come back to where it was.
TEST(AnalysisReport, RefusingANonDatabaseReleasesItsConnection) {
  const test::ScratchDir dir;
  const std::string text = dir.write("text.db", std::string(4096, 'x'));
  EXPECT_THROW(load_databases({text}), StoreError);  // SQLite's first allocations happen here
  const sqlite3_int64 before = sqlite3_memory_used();
  for (int i = 0; i < 3; ++i) EXPECT_THROW(load_databases({text}), StoreError);
  EXPECT_EQ(sqlite3_memory_used(), before);
}

TEST(AnalysisReport, AnalyzeCommandWritesReportCsvAndFigures) {
  const test::ScratchDir dir;
  const std::string preference = ritschel_database(dir);
  const std::string hard = hard_cases_database(dir, "P1");
  const auto out = dir.path() / "out";
  const test::RunOutput run =
      test::run_glarelab({"analyze", preference, hard, "--out", out.string(), "--bootstrap", "20"}, dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("Analysed 3 session(s)"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("forced choice pooled: instruction=brighter: 'dynamic' over 'static' in 54 of 80"),
            std::string::npos)
      << run.output;
  for (const char* file : {"report.html", "trials.csv", "frames.csv", "tracker_samples.csv", "figures/forced_choice.svg",
                           "figures/staircase_1.svg", "figures/psychometric_2.svg", "figures/adjustment.svg",
                           "figures/rating_1.svg", "figures/response_times.svg"}) {
    EXPECT_TRUE(std::filesystem::exists(out / file)) << file;
  }
  const test::RunOutput missing = test::run_glarelab({"analyze", dir.file("nope.db")}, dir.path());
  EXPECT_NE(missing.exit_code, 0);
}

}  // namespace
}  // namespace glarelab::analysis

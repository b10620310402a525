#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "runner/store/result_store.h"
#include "tests/raw_db.h"
#include "tests/scratch_dir.h"

namespace glarelab {
namespace {

using ::testing::HasSubstr;

using test::RawDb;

std::vector<std::string> column_names(const RawDb& db, const std::string& table) {
  std::vector<std::string> names;
  for (const auto& row : db.rows("PRAGMA table_info(" + table + ")")) names.push_back(row[1]);
  return names;
}

// First column of every index on `table`.
std::set<std::string> indexed_columns(const RawDb& db, const std::string& table) {
  std::set<std::string> columns;
  for (const auto& row : db.rows("PRAGMA index_list(" + table + ")")) {
    const auto info = db.rows("PRAGMA index_info(" + row[1] + ")");
    if (!info.empty()) columns.insert(info[0][2]);
  }
  return columns;
}

SessionRecord sample_session() {
  SessionRecord session;
  session.experiment = "disability_glare";
  session.participant = "P07";
  session.seed = 0xFEDCBA9876543210ULL;  // above 2^63: exercises the int64 bit-cast
  session.started_utc = "2026-11-21T16:30:00.123Z";
  session.config = "[experiment]\nname = \"disability_glare\"\n";
  session.software_version = "0.1.0-test";
  session.renderer = "llvmpipe";
  session.display_backend = "offscreen";
  session.clock = "virtual";
  session.observer = "simulated:ideal";
  return session;
}

TrialRecord full_trial(std::int64_t session_id, int index) {
  TrialRecord trial;
  trial.session_id = session_id;
  trial.trial_index = index;
  trial.block = 2;
  trial.procedure = "staircase";
  trial.condition = R"({"glare_angle_deg": 5, "contrast": 0.1})";
  trial.intensity = 0.0371;
  trial.response = "left";
  trial.correct = 1;
  trial.response_time_s = 0.6125;
  trial.onset_s = 12.25;
  trial.staircase = "3down1up";
  trial.reversal = 0;
  trial.started_utc = "2026-11-21T16:30:12.000Z";
  return trial;
}

TrialRecord sparse_trial(std::int64_t session_id, int index) {
  TrialRecord trial;
  trial.session_id = session_id;
  trial.trial_index = index;
  trial.block = 0;
  trial.procedure = "rating";
  trial.condition = "{}";
  trial.response = "";
  trial.onset_s = 20.5;
  trial.started_utc = "2026-11-21T16:30:20.000Z";
  return trial;
}

std::vector<FrameRecord> frames_from(double start_s, int count) {
  std::vector<FrameRecord> frames;
  for (int i = 0; i < count; ++i) {
    frames.push_back({i, start_s + i / 60.0, start_s + i / 60.0 + 0.0001, i == 2, {}});
  }
  return frames;
}

void expect_same_trial(const TrialRecord& expected, const TrialRecord& actual) {
  EXPECT_EQ(actual.session_id, expected.session_id);
  EXPECT_EQ(actual.trial_index, expected.trial_index);
  EXPECT_EQ(actual.block, expected.block);
  EXPECT_EQ(actual.procedure, expected.procedure);
  EXPECT_EQ(actual.condition, expected.condition);
  EXPECT_EQ(actual.intensity, expected.intensity);
  EXPECT_EQ(actual.response, expected.response);
  EXPECT_EQ(actual.correct, expected.correct);
  EXPECT_EQ(actual.response_time_s, expected.response_time_s);
  EXPECT_EQ(actual.onset_s, expected.onset_s);
  EXPECT_EQ(actual.staircase, expected.staircase);
  EXPECT_EQ(actual.reversal, expected.reversal);
  EXPECT_EQ(actual.started_utc, expected.started_utc);
}

TEST(Store, SchemaVersionAndContractColumns) {
  test::ScratchDir dir;
  // The parent directories do not exist yet: the store creates them.
  const std::string path = dir.file("nested/results/glarelab.db");
  {
    ResultStore store(path);
    EXPECT_EQ(store.schema_version(), 6);
    EXPECT_EQ(store.path(), path);
  }
  RawDb db(path);
  EXPECT_EQ(db.value("PRAGMA user_version"), "6");
  EXPECT_THAT(column_names(db, "adjustments"), ::testing::ElementsAre("trial_id", "spot", "value_cd_m2"));
  EXPECT_THAT(column_names(db, "sessions"),
              ::testing::IsSupersetOf({"id", "experiment", "participant", "seed", "started_utc", "finished_utc",
                                       "status", "config", "software_version", "renderer", "display_backend", "clock",
                                       "observer"}));
  EXPECT_THAT(column_names(db, "trials"),
              ::testing::IsSupersetOf({"id", "session_id", "trial_index", "block", "procedure", "condition",
                                       "intensity", "response", "correct", "response_time_s", "onset_s", "staircase",
                                       "reversal", "started_utc"}));
  EXPECT_THAT(column_names(db, "frames"),
              ::testing::IsSupersetOf({"session_id", "trial_id", "frame_index", "scheduled_s", "flip_s", "dropped"}));
  EXPECT_THAT(column_names(db, "tracker_samples"),
              ::testing::IsSupersetOf({"session_id", "eye", "device_time_s", "session_time_s", "pupil_diameter_mm",
                                       "gaze_x", "gaze_y", "confidence", "valid"}));
  EXPECT_THAT(column_names(db, "session_events"),
              ::testing::IsSupersetOf({"id", "session_id", "session_time_s", "wall_utc", "kind", "message"}));
  EXPECT_THAT(indexed_columns(db, "trials"), ::testing::Contains("session_id"));
  EXPECT_THAT(indexed_columns(db, "frames"), ::testing::Contains("trial_id"));
  EXPECT_THAT(indexed_columns(db, "tracker_samples"), ::testing::Contains("session_id"));
}

TEST(Store, ConnectionSettings) {
  test::ScratchDir dir;
  const std::string path = dir.file("results.db");
  ResultStore store(path);
  // The store's own connection.
  const auto pragma = [&store](const char* sql) {
    sqlite3_stmt* statement = nullptr;
    EXPECT_EQ(sqlite3_prepare_v2(store.handle(), sql, -1, &statement, nullptr), SQLITE_OK);
    std::string value;
    if (sqlite3_step(statement) == SQLITE_ROW) value = reinterpret_cast<const char*>(sqlite3_column_text(statement, 0));
    sqlite3_finalize(statement);
    return value;
  };
  EXPECT_EQ(pragma("PRAGMA journal_mode"), "wal");
  EXPECT_EQ(pragma("PRAGMA synchronous"), "2");  // FULL
  EXPECT_EQ(pragma("PRAGMA foreign_keys"), "1");
  EXPECT_EQ(pragma("PRAGMA busy_timeout"), "5000");
  // WAL is a property of the file: a fresh connection sees it too.
  RawDb other(path);
  EXPECT_EQ(other.value("PRAGMA journal_mode"), "wal");
}

// Sessions started together on one new file (SessionFailure.TwoRunsStartedTogether...) each open
// a store on it, and each switches it to WAL. One process's switch meeting another's read and
// write fails at once with SQLITE_BUSY, whatever the busy timeout (SQLite breaks the deadlock of two
// readers that both want to write by refusing one): before, 33 of 800 stores opened eight
// processes at a time failed with "setting journal_mode=WAL: database is locked". Eighty rounds of
// eight processes, each opening a store on a new file and writing a session to it: every one opens
// and writes.
TEST(Store, EightProcessesOpeningOneNewFileTogetherAllOpenIt) {
  test::ScratchDir dir;
  constexpr int kRounds = 80, kProcesses = 8;
  int failed = 0;
  for (int round = 0; round < kRounds; ++round) {
    const std::string path = dir.file("new_" + std::to_string(round) + ".db");
    std::vector<pid_t> children;
    for (int p = 0; p < kProcesses; ++p) {
      const pid_t child = ::fork();
      ASSERT_GE(child, 0) << "fork";
      if (child == 0) {
        // The child only opens the store and writes: no gtest assertion runs in it.
        try {
          ResultStore store(path);
          store.begin_session(sample_session());
          ::_exit(0);
        } catch (const std::exception& error) {
          std::fprintf(stderr, "round %d, process %d: %s\n", round, p, error.what());
          ::_exit(1);
        }
      }
      children.push_back(child);
    }
    for (const pid_t child : children) {
      int status = 0;
      ASSERT_EQ(::waitpid(child, &status, 0), child);
      if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) ++failed;
    }
    EXPECT_EQ(RawDb(path).value("SELECT count(*) FROM sessions"), std::to_string(kProcesses)) << "round " << round;
  }
  EXPECT_EQ(failed, 0) << "of " << kRounds * kProcesses << " stores opened (the failures' errors above)";
}

TEST(Store, FilesAreOwnerOnly) {
  test::ScratchDir dir;
  const std::string path = dir.file("results.db");
  // With a permissive umask, a file created by sqlite3_open would be 0644. Restored on every
  // exit from the test, including a failed ASSERT.
  struct UmaskGuard {
    mode_t previous = ::umask(022);
    ~UmaskGuard() { ::umask(previous); }
  } umask_guard;
  {
    ResultStore store(path);
    const auto session = store.begin_session(sample_session());
    store.commit_trial(full_trial(session, 0), frames_from(1.0, 3));
    struct stat info {};
    ASSERT_EQ(::stat(path.c_str(), &info), 0);
    EXPECT_EQ(info.st_mode & 0777, 0600u);
    ASSERT_EQ(::stat((path + "-wal").c_str(), &info), 0) << "WAL file expected while the store is open";
    EXPECT_EQ(info.st_mode & 0777, 0600u);
  }
}

TEST(Store, CommitReopenAndLoadGivesIdenticalFields) {
  test::ScratchDir dir;
  const std::string path = dir.file("results.db");
  const SessionRecord session = sample_session();
  std::int64_t session_id = 0;
  TrialRecord full;
  TrialRecord sparse;
  const auto full_frames = frames_from(12.25, 5);
  {
    ResultStore store(path);
    session_id = store.begin_session(session);
    full = full_trial(session_id, 0);
    sparse = sparse_trial(session_id, 1);
    full.id = store.commit_trial(full, full_frames);
    sparse.id = store.commit_trial(sparse, {});
  }
  ResultStore store(path);
  const auto loaded = store.load_session(session_id);
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(loaded->id, session_id);
  EXPECT_EQ(loaded->experiment, session.experiment);
  EXPECT_EQ(loaded->participant, session.participant);
  EXPECT_EQ(loaded->seed, session.seed);
  EXPECT_EQ(loaded->started_utc, session.started_utc);
  EXPECT_EQ(loaded->finished_utc, "");
  EXPECT_EQ(loaded->status, "running");
  EXPECT_EQ(loaded->config, session.config);
  EXPECT_EQ(loaded->software_version, session.software_version);
  EXPECT_EQ(loaded->renderer, session.renderer);
  EXPECT_EQ(loaded->display_backend, session.display_backend);
  EXPECT_EQ(loaded->clock, session.clock);
  EXPECT_EQ(loaded->observer, session.observer);
  EXPECT_FALSE(store.load_session(session_id + 100).has_value());
  ASSERT_EQ(store.load_sessions().size(), 1u);

  const auto trials = store.load_trials(session_id);
  ASSERT_EQ(trials.size(), 2u);
  EXPECT_EQ(trials[0].id, full.id);
  EXPECT_EQ(trials[1].id, sparse.id);
  expect_same_trial(full, trials[0]);
  expect_same_trial(sparse, trials[1]);

  const auto frames = store.load_frames(full.id);
  ASSERT_EQ(frames.size(), full_frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(frames[i].frame_index, full_frames[i].frame_index);
    EXPECT_EQ(frames[i].scheduled_s, full_frames[i].scheduled_s);
    EXPECT_EQ(frames[i].flip_s, full_frames[i].flip_s);
    EXPECT_EQ(frames[i].dropped, full_frames[i].dropped);
  }
  EXPECT_TRUE(store.load_frames(sparse.id).empty());

  // What is in the file, read independently: NULLs where the record had none, and the seed
  // as the int64 with the same bits.
  RawDb db(path);
  EXPECT_EQ(db.rows("SELECT intensity IS NULL, correct IS NULL, response_time_s IS NULL, staircase IS NULL, "
                    "reversal IS NULL FROM trials WHERE trial_index = 1")[0],
            (std::vector<std::string>{"1", "1", "1", "1", "1"}));
  EXPECT_EQ(db.rows("SELECT intensity IS NULL, correct IS NULL, response_time_s IS NULL, staircase IS NULL, "
                    "reversal IS NULL FROM trials WHERE trial_index = 0")[0],
            (std::vector<std::string>{"0", "0", "0", "0", "0"}));
  EXPECT_EQ(db.value("SELECT seed FROM sessions"), std::to_string(static_cast<std::int64_t>(0xFEDCBA9876543210ULL)));
  EXPECT_EQ(db.value("SELECT finished_utc IS NULL FROM sessions"), "1");
  EXPECT_EQ(db.value("SELECT COUNT(*) FROM frames WHERE session_id = " + std::to_string(session_id)), "5");
}

TEST(Store, DuplicateTrialIndexIsRefusedAndRolledBack) {
  test::ScratchDir dir;
  const std::string path = dir.file("results.db");
  ResultStore store(path);
  const auto session = store.begin_session(sample_session());
  store.commit_trial(full_trial(session, 0), frames_from(1.0, 4));
  try {
    store.commit_trial(full_trial(session, 0), frames_from(2.0, 7));
    FAIL() << "duplicate (session_id, trial_index) was accepted";
  } catch (const StoreError& error) {
    EXPECT_THAT(error.what(), HasSubstr("SQLite: " + path + ": "));
    EXPECT_THAT(error.what(), HasSubstr("UNIQUE"));
  }
  const auto trials = store.load_trials(session);
  ASSERT_EQ(trials.size(), 1u);
  expect_same_trial(full_trial(session, 0), trials[0]);
  EXPECT_EQ(store.frame_count(session), 4);
  // No transaction was left open: the next trial commits and is durable.
  store.commit_trial(full_trial(session, 1), frames_from(3.0, 2));
  EXPECT_EQ(store.load_trials(session).size(), 2u);
  EXPECT_EQ(RawDb(path).value("SELECT COUNT(*) FROM frames"), "6");
}

TEST(Store, TrialOfUnknownSessionViolatesForeignKey) {
  test::ScratchDir dir;
  ResultStore store(dir.file("results.db"));
  EXPECT_THROW(store.commit_trial(full_trial(42, 0), frames_from(0.0, 1)), StoreError);
  EXPECT_EQ(store.frame_count(42), 0);
}

// Version 2 (before gaze_age_s): its frames gain the column, empty, and keep their values; a live
// glare frame's gaze age written now reads back.
TEST(Store, VersionTwoDatabaseGainsGazeAgeAndKeepsItsFrames) {
  test::ScratchDir dir;
  const std::string path = dir.file("v2.db");
  std::int64_t session_id = 0;
  {
    ResultStore store(path);
    session_id = store.begin_session(sample_session());
    store.commit_trial(full_trial(session_id, 0), frames_from(0.0, 2));
  }
  {
    RawDb db(path, true);
    db.exec("DROP TABLE session_owners; ALTER TABLE frames DROP COLUMN gaze_age_s; PRAGMA user_version = 2;");
  }
  ResultStore store(path);
  EXPECT_EQ(store.schema_version(), 6);
  const auto trials = store.load_trials(session_id);
  ASSERT_EQ(trials.size(), 1u);
  const auto old_frames = store.load_frames(trials[0].id);
  ASSERT_EQ(old_frames.size(), 2u);
  EXPECT_FALSE(old_frames[0].gaze_age_s.has_value());
  std::vector<FrameRecord> live = frames_from(1.0, 2);
  live[1].gaze_age_s = 0.0375;
  const std::int64_t trial_id = store.commit_trial(full_trial(session_id, 1), live);
  const auto frames = store.load_frames(trial_id);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_FALSE(frames[0].gaze_age_s.has_value());
  ASSERT_TRUE(frames[1].gaze_age_s.has_value());
  EXPECT_EQ(*frames[1].gaze_age_s, 0.0375);
}

TEST(Store, NewerSchemaIsRefused) {
  test::ScratchDir dir;
  const std::string path = dir.file("future.db");
  {
    RawDb db(path, true);
    db.exec("CREATE TABLE sessions (id INTEGER PRIMARY KEY); PRAGMA user_version = 7;");
  }
  try {
    ResultStore store(path);
    FAIL() << "a database from a newer glarelab was opened";
  } catch (const StoreError& error) {
    EXPECT_EQ(std::string(error.what()), path + ": schema version 7 is newer than this glarelab (6)");
  }
  EXPECT_EQ(RawDb(path).value("PRAGMA user_version"), "7");
}

TEST(Store, VersionOneDatabaseGainsTheAdjustmentsTableAndKeepsItsTrials) {
  test::ScratchDir dir;
  const std::string path = dir.file("v1.db");
  std::int64_t session_id = 0;
  {
    ResultStore store(path);
    session_id = store.begin_session(sample_session());
    store.commit_trial(full_trial(session_id, 0), frames_from(0.0, 2));
  }
  {
    // What a glarelab of schema version 1 left behind: no adjustments table, no gaze_age_s.
    RawDb db(path, true);
    db.exec(
        "DROP TABLE session_owners; DROP TABLE adjustments; ALTER TABLE frames DROP COLUMN gaze_age_s; "
        "PRAGMA user_version = 1;");
  }
  ResultStore store(path);
  EXPECT_EQ(store.schema_version(), 6);
  ASSERT_EQ(store.load_trials(session_id).size(), 1u);
  TrialRecord adjustment = full_trial(session_id, 1);
  adjustment.procedure = "adjustment";
  const std::int64_t trial_id =
      store.commit_trial(adjustment, frames_from(1.0, 1), {{1, 118.5}, {0, 97.25}});
  const auto settings = store.load_adjustments(trial_id);
  ASSERT_EQ(settings.size(), 2u);
  EXPECT_EQ(settings[0].spot, 0);
  EXPECT_EQ(settings[0].value_cd_m2, 97.25);
  EXPECT_EQ(settings[1].spot, 1);
  EXPECT_EQ(settings[1].value_cd_m2, 118.5);
}

TEST(Store, TextFileIsRefusedNamingIt) {
  test::ScratchDir dir;
  const std::string path = dir.file("notes.db");
  std::string text;
  for (int i = 0; i < 200; ++i) text += "participant notes, line " + std::to_string(i) + "\n";
  test::write_bytes(path, text);
  try {
    ResultStore store(path);
    FAIL() << "a text file was opened as a database";
  } catch (const StoreError& error) {
    EXPECT_THAT(error.what(), HasSubstr(path));
    EXPECT_THAT(error.what(), HasSubstr("not a database"));
  }
  EXPECT_EQ(test::read_bytes(path), text) << "the refused file was modified";
}

TEST(Store, IntegrityCheckIsOk) {
  test::ScratchDir dir;
  ResultStore store(dir.file("results.db"));
  const auto session = store.begin_session(sample_session());
  store.commit_trial(full_trial(session, 0), frames_from(0.0, 10));
  EXPECT_EQ(store.integrity_check(), "ok");
}

TEST(Store, FinishAndReopenSession) {
  test::ScratchDir dir;
  const std::string path = dir.file("results.db");
  ResultStore store(path);
  const auto session = store.begin_session(sample_session());
  store.finish_session(session, "completed");
  auto loaded = store.load_session(session);
  ASSERT_TRUE(loaded);
  EXPECT_EQ(loaded->status, "completed");
  EXPECT_TRUE(std::regex_match(loaded->finished_utc, std::regex(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z)")))
      << loaded->finished_utc;

  store.reopen_session(session);
  loaded = store.load_session(session);
  EXPECT_EQ(loaded->status, "running");
  EXPECT_EQ(loaded->finished_utc, "");
  EXPECT_EQ(RawDb(path).value("SELECT finished_utc IS NULL FROM sessions"), "1");

  store.finish_session(session, "aborted");
  EXPECT_EQ(store.load_session(session)->status, "aborted");
  EXPECT_THROW(store.finish_session(session, "running"), StoreError);
  EXPECT_THROW(store.finish_session(session, "done"), StoreError);
  EXPECT_THROW(store.finish_session(session + 1, "completed"), StoreError);
  EXPECT_THROW(store.reopen_session(session + 1), StoreError);
}

TEST(Store, LastFlipAndFrameCount) {
  test::ScratchDir dir;
  ResultStore store(dir.file("results.db"));
  const auto first = store.begin_session(sample_session());
  const auto second = store.begin_session(sample_session());
  EXPECT_EQ(store.last_flip_s(first), 0.0);
  EXPECT_EQ(store.frame_count(first), 0);
  store.commit_trial(full_trial(first, 0), {{0, 1.0, 1.5, false, {}}, {1, 2.0, 7.25, false, {}}, {2, 3.0, 3.5, true, {}}});
  store.commit_trial(full_trial(first, 1), {{0, 4.0, 4.5, false, {}}});
  store.commit_trial(full_trial(second, 0), {{0, 100.0, 100.5, false, {}}});
  EXPECT_EQ(store.last_flip_s(first), 7.25);
  EXPECT_EQ(store.frame_count(first), 4);
  EXPECT_EQ(store.last_flip_s(second), 100.5);
  EXPECT_EQ(store.frame_count(second), 1);
}

TEST(Store, TrackerSamplesAndEvents) {
  test::ScratchDir dir;
  const std::string path = dir.file("results.db");
  ResultStore store(path);
  const auto session = store.begin_session(sample_session());
  std::vector<TrackerSampleRecord> samples(3);
  samples[0] = {0, 10.0, 1.0, 3.5, 0.25, -0.5, 0.9, true};
  samples[1] = {1, 10.004, 1.004, std::nullopt, std::nullopt, std::nullopt, 0.0, false};
  samples[2] = {0, 10.008, 1.008, 3.6, 0.26, -0.49, 0.95, true};
  store.append_tracker_samples(session, samples);
  store.log_event(session, 1.5, "warning", "dropped frame at 1.5 s");

  RawDb db(path);
  EXPECT_EQ(db.rows("SELECT eye, pupil_diameter_mm, gaze_x, valid FROM tracker_samples ORDER BY device_time_s"),
            (std::vector<std::vector<std::string>>{
                {"0", "3.5", "0.25", "1"}, {"1", "NULL", "NULL", "0"}, {"0", "3.6", "0.26", "1"}}));
  const auto events = db.rows("SELECT session_id, session_time_s, kind, message, wall_utc FROM session_events");
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0][0], std::to_string(session));
  EXPECT_EQ(events[0][1], "1.5");
  EXPECT_EQ(events[0][2], "warning");
  EXPECT_EQ(events[0][3], "dropped frame at 1.5 s");
  EXPECT_TRUE(std::regex_match(events[0][4], std::regex(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z)")));
}

TEST(Store, UtcNowIsIso8601AndCurrent) {
  const std::time_t before = std::time(nullptr);
  const std::string now = utc_now_iso8601();
  const std::time_t after = std::time(nullptr);
  ASSERT_TRUE(std::regex_match(now, std::regex(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z)"))) << now;
  // Independent reference: format time(nullptr) with gmtime and compare to the second.
  const auto format = [](std::time_t t) {
    std::tm utc{};
    gmtime_r(&t, &utc);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &utc);
    return std::string(text);
  };
  const std::string seconds = now.substr(0, 19);
  // Between the two readings (which a loaded machine may set seconds apart): ISO 8601 text of one
  // format orders like the times it names.
  EXPECT_TRUE(format(before) <= seconds && seconds <= format(after)) << now;
}

}  // namespace
}  // namespace glarelab

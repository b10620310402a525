// Schema version 4: the trials table rebuilt to take procedure 'timing_test'. A version-3 database
// (its trials table as version 3 made it) migrates with its trials, frames and adjustments kept,
// foreign keys enforced again afterwards, and the trial index back in place.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <string>
#include <vector>

#include "runner/store/result_store.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

// The trials table of schema versions 1 to 3 (runner/store/schema_migrations.cpp, 0 -> 1).
constexpr const char* kVersion3Trials = R"sql(
CREATE TABLE trials_v3 (
  id INTEGER PRIMARY KEY,
  session_id INTEGER NOT NULL REFERENCES sessions(id),
  trial_index INTEGER NOT NULL,
  block INTEGER NOT NULL,
  procedure TEXT NOT NULL CHECK(procedure IN ('forced_choice','staircase','quest','adjustment','rating')),
  condition TEXT NOT NULL,
  intensity REAL,
  response TEXT NOT NULL,
  correct INTEGER CHECK(correct IN (0, 1)),
  response_time_s REAL,
  onset_s REAL NOT NULL,
  staircase TEXT,
  reversal INTEGER,
  started_utc TEXT NOT NULL,
  UNIQUE(session_id, trial_index)
);
INSERT INTO trials_v3 SELECT * FROM trials;
DROP TABLE trials;
ALTER TABLE trials_v3 RENAME TO trials;
CREATE INDEX trials_session_id ON trials(session_id);
DROP TABLE session_owners;
PRAGMA user_version = 3;
)sql";

int exec(sqlite3* db, const std::string& sql) { return sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr); }

std::string text_value(sqlite3* db, const std::string& sql) {
  sqlite3_stmt* statement = nullptr;
  std::string value = "<none>";
  if (sqlite3_prepare_v2(db, sql.c_str(), -1, &statement, nullptr) == SQLITE_OK && sqlite3_step(statement) == SQLITE_ROW)
    value = reinterpret_cast<const char*>(sqlite3_column_text(statement, 0));
  sqlite3_finalize(statement);
  return value;
}

SessionRecord session_record() {
  SessionRecord session;
  session.experiment = "demo";
  session.participant = "p1";
  session.started_utc = "2026-11-24T08:00:00.000Z";
  session.status = "running";
  session.config = "[experiment]\n";
  session.software_version = "test";
  session.renderer = "test";
  session.display_backend = "offscreen";
  session.clock = "virtual";
  session.observer = "simulated";
  return session;
}

TrialRecord trial_record(std::int64_t session_id, int index, const std::string& procedure) {
  TrialRecord trial;
  trial.session_id = session_id;
  trial.trial_index = index;
  trial.procedure = procedure;
  trial.condition = "{}";
  trial.response = procedure == "timing_test" ? "" : "left";
  trial.onset_s = index;
  trial.started_utc = "2026-11-24T08:00:01.000Z";
  return trial;
}

TEST(TimingTestStore, VersionThreeDatabaseMigratesKeepingTrialsFramesAndForeignKeys) {
  const test::ScratchDir dir;
  const std::string path = dir.file("v3.db");
  std::int64_t session_id = 0, adjustment_id = 0;
  {
    ResultStore store(path);
    session_id = store.begin_session(session_record());
    store.commit_trial(trial_record(session_id, 0, "forced_choice"), {{0, 0.0, 0.0, false, {}}, {1, 0.1, 0.1, false, 0.02}});
    adjustment_id = store.commit_trial(trial_record(session_id, 1, "adjustment"), {{0, 1.0, 1.0, true, {}}}, {{0, 97.25}});
  }
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    ASSERT_EQ(exec(db, kVersion3Trials), SQLITE_OK) << sqlite3_errmsg(db);
    // Version 3 really refused the new procedure.
    EXPECT_NE(exec(db, "INSERT INTO trials (session_id, trial_index, block, procedure, condition, response, onset_s, "
                       "started_utc) VALUES (1, 9, 0, 'timing_test', '{}', '', 0, 'x')"),
              SQLITE_OK);
    sqlite3_close(db);
  }

  ResultStore store(path);
  EXPECT_EQ(store.schema_version(), 6);
  const auto trials = store.load_trials(session_id);
  ASSERT_EQ(trials.size(), 2u);
  EXPECT_EQ(trials[0].procedure, "forced_choice");
  EXPECT_EQ(trials[1].id, adjustment_id);
  const auto frames = store.load_frames(trials[0].id);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(*frames[1].gaze_age_s, 0.02);
  ASSERT_EQ(store.load_adjustments(adjustment_id).size(), 1u);
  EXPECT_EQ(store.load_adjustments(adjustment_id)[0].value_cd_m2, 97.25);
  // The new procedure is taken, with its flips.
  const std::int64_t timing = store.commit_trial(trial_record(session_id, 2, "timing_test"), {{0, 2.0, 2.0, false, {}}});
  EXPECT_EQ(store.load_frames(timing).size(), 1u);
  // Foreign keys are on again and every reference resolves to the rebuilt table.
  sqlite3* db = store.handle();
  EXPECT_EQ(text_value(db, "PRAGMA foreign_keys"), "1");
  EXPECT_EQ(text_value(db, "PRAGMA foreign_key_check"), "<none>");
  EXPECT_NE(exec(db, "INSERT INTO frames (session_id, trial_id, frame_index, scheduled_s, flip_s, dropped) "
                     "VALUES (1, 999, 0, 0, 0, 0)"),
            SQLITE_OK)
      << "a frame of a trial that does not exist is refused";
  EXPECT_EQ(text_value(db, "SELECT name FROM sqlite_master WHERE type = 'index' AND name = 'trials_session_id'"),
            "trials_session_id");
  EXPECT_EQ(store.integrity_check(), "ok");
}

}  // namespace
}  // namespace glarelab

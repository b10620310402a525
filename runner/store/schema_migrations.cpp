// The SQL that builds a results database version by version (docs/DATABASE.md "Schema version").
#include "runner/store/schema_migrations.h"

#include <iterator>

namespace glarelab {

// Schema migrations, in order: kSchemaMigrations[i] upgrades user_version i to i + 1. Each runs in
// its own transaction together with the user_version bump, so a crash leaves the database at
// a whole version. Published scripts are never edited; a schema change appends a script.
const char* const kSchemaMigrations[] = {
    // 0 -> 1: the DESIGN contract tables.
    R"sql(
CREATE TABLE sessions (
  id INTEGER PRIMARY KEY,
  experiment TEXT NOT NULL,
  participant TEXT NOT NULL,
  seed INTEGER NOT NULL,
  started_utc TEXT NOT NULL,
  finished_utc TEXT,
  status TEXT NOT NULL CHECK(status IN ('running','completed','aborted')),
  config TEXT NOT NULL,
  software_version TEXT NOT NULL,
  renderer TEXT NOT NULL,
  display_backend TEXT NOT NULL,
  clock TEXT NOT NULL,
  observer TEXT NOT NULL
);
CREATE TABLE trials (
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
CREATE TABLE frames (
  session_id INTEGER NOT NULL REFERENCES sessions(id),
  trial_id INTEGER NOT NULL REFERENCES trials(id),
  frame_index INTEGER NOT NULL,
  scheduled_s REAL NOT NULL,
  flip_s REAL NOT NULL,
  dropped INTEGER NOT NULL CHECK(dropped IN (0, 1))
);
CREATE TABLE tracker_samples (
  session_id INTEGER NOT NULL REFERENCES sessions(id),
  eye INTEGER NOT NULL,
  device_time_s REAL NOT NULL,
  session_time_s REAL NOT NULL,
  pupil_diameter_mm REAL,
  gaze_x REAL,
  gaze_y REAL,
  confidence REAL NOT NULL,
  valid INTEGER NOT NULL CHECK(valid IN (0, 1))
);
CREATE TABLE session_events (
  id INTEGER PRIMARY KEY,
  session_id INTEGER NOT NULL REFERENCES sessions(id),
  session_time_s REAL NOT NULL,
  wall_utc TEXT NOT NULL,
  kind TEXT NOT NULL,
  message TEXT NOT NULL
);
CREATE INDEX trials_session_id ON trials(session_id);
CREATE INDEX frames_trial_id ON frames(trial_id);
-- last_flip_s and frame_count look frames up by session on resume.
CREATE INDEX frames_session_id ON frames(session_id);
CREATE INDEX tracker_samples_session_id ON tracker_samples(session_id);
CREATE INDEX session_events_session_id ON session_events(session_id);
)sql",
    // 1 -> 2: the settings of double-adjustment trials (two comparison spots per trial).
    R"sql(
CREATE TABLE adjustments (
  trial_id INTEGER NOT NULL REFERENCES trials(id),
  spot INTEGER NOT NULL CHECK(spot IN (0, 1)),
  value_cd_m2 REAL NOT NULL,
  PRIMARY KEY (trial_id, spot)
);
)sql",
    // 2 -> 3: how old the gaze was at each live glare frame's flip (gaze-to-flip latency).
    R"sql(
ALTER TABLE frames ADD COLUMN gaze_age_s REAL;
)sql",
    // 3 -> 4: `glarelab timing-test` stores its flips as one trial of procedure 'timing_test'.
    // SQLite cannot alter a CHECK constraint, so the trials table is rebuilt with the wider one
    // (the procedure of the SQLite manual, "Making Other Kinds Of Table Schema Changes"); the
    // store runs migrations with foreign keys off, so dropping the old table leaves the frames'
    // and adjustments' references to be resolved by the renamed one.
    R"sql(
CREATE TABLE trials_v4 (
  id INTEGER PRIMARY KEY,
  session_id INTEGER NOT NULL REFERENCES sessions(id),
  trial_index INTEGER NOT NULL,
  block INTEGER NOT NULL,
  procedure TEXT NOT NULL CHECK(procedure IN ('forced_choice','staircase','quest','adjustment','rating','timing_test')),
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
INSERT INTO trials_v4 (id, session_id, trial_index, block, procedure, condition, intensity, response, correct,
                       response_time_s, onset_s, staircase, reversal, started_utc)
  SELECT id, session_id, trial_index, block, procedure, condition, intensity, response, correct,
         response_time_s, onset_s, staircase, reversal, started_utc FROM trials;
DROP TABLE trials;
ALTER TABLE trials_v4 RENAME TO trials;
CREATE INDEX trials_session_id ON trials(session_id);
)sql",
    // 4 -> 5: the process that runs a session, one at a time (runner/store/session_lease.h).
    R"sql(
CREATE TABLE session_owners (
  session_id INTEGER PRIMARY KEY REFERENCES sessions(id),
  pid INTEGER NOT NULL,
  process_start_ticks INTEGER NOT NULL,
  boot_id TEXT NOT NULL,
  host TEXT NOT NULL,
  since_utc TEXT NOT NULL
);
)sql",
    // 5 -> 6: the straylight measurement's trials, procedure 'straylight' (docs/STRAYLIGHT.md): the
    // trials table rebuilt with the wider CHECK as in 3 -> 4, its rows and ids kept.
    R"sql(
CREATE TABLE trials_v6 (
  id INTEGER PRIMARY KEY,
  session_id INTEGER NOT NULL REFERENCES sessions(id),
  trial_index INTEGER NOT NULL,
  block INTEGER NOT NULL,
  procedure TEXT NOT NULL
    CHECK(procedure IN ('forced_choice','staircase','quest','adjustment','rating','timing_test','straylight')),
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
INSERT INTO trials_v6 (id, session_id, trial_index, block, procedure, condition, intensity, response, correct,
                       response_time_s, onset_s, staircase, reversal, started_utc)
  SELECT id, session_id, trial_index, block, procedure, condition, intensity, response, correct,
         response_time_s, onset_s, staircase, reversal, started_utc FROM trials;
DROP TABLE trials;
ALTER TABLE trials_v6 RENAME TO trials;
CREATE INDEX trials_session_id ON trials(session_id);
)sql",
};
static_assert(std::size(kSchemaMigrations) == kResultsSchemaVersion, "one migration per schema version");

}  // namespace glarelab

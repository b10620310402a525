#pragma once
// The results database (SQLite). Contract (docs/DATABASE.md, ../DESIGN.md):
//  - tables sessions, trials, frames, tracker_samples, session_events, with the DESIGN minimum
//    columns (never renamed) and a schema version in PRAGMA user_version, upgraded by migrations;
//  - WAL journal with synchronous=FULL; a trial and its frames are one transaction, committed
//    before the next trial starts, so a killed run loses at most the trial in progress;
//  - the database file is created with owner-only permissions (0600).
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

struct sqlite3;

namespace glarelab {

class StoreError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct SessionRecord {
  std::int64_t id = 0;
  std::string experiment;
  std::string participant;
  std::uint64_t seed = 0;
  std::string started_utc;   // ISO 8601, "2026-11-21T16:30:00.123Z"
  std::string finished_utc;  // empty while running
  std::string status;        // running | completed | aborted
  std::string config;        // the fully resolved experiment (TOML)
  std::string software_version;
  std::string renderer;      // GL_RENDERER / backend description
  std::string display_backend;  // window | offscreen
  std::string clock;            // monotonic | virtual
  std::string observer;         // keyboard | simulated[:NAME] | script:FILE
};

struct TrialRecord {
  std::int64_t id = 0;
  std::int64_t session_id = 0;
  int trial_index = 0;  // from 0 within a session
  int block = 0;
  std::string procedure;  // forced_choice | staircase | quest | adjustment | rating
  std::string condition;  // JSON object of the condition row
  std::optional<double> intensity;
  std::string response;
  std::optional<int> correct;  // 1, 0 or NULL
  std::optional<double> response_time_s;
  double onset_s = 0.0;  // session clock, flip of the first stimulus frame
  std::string staircase;  // empty -> NULL
  std::optional<int> reversal;
  std::string started_utc;  // wall clock (not reproducible; excluded from determinism checks)
};

struct FrameRecord {
  // Stimulus frames: 0, 1, ... within the trial (on across both intervals of a sequential trial).
  // The trial's other flips (screens, fixation, intervals between, response, feedback): -1, -2, ...
  // in flip order (docs/DATABASE.md).
  int frame_index = 0;
  double scheduled_s = 0.0;
  double flip_s = 0.0;
  bool dropped = false;
};

// One setting of a double-adjustment trial (Yoshida 2008): which comparison spot and the
// luminance it was left at.
struct AdjustmentSetting {
  int spot = 0;  // 0: left of the target, 1: right
  double value_cd_m2 = 0.0;
};

struct TrackerSampleRecord {
  int eye = 0;
  double device_time_s = 0.0;
  double session_time_s = 0.0;
  std::optional<double> pupil_diameter_mm;
  std::optional<double> gaze_x;
  std::optional<double> gaze_y;
  double confidence = 0.0;
  bool valid = false;
};

class ResultStore {
 public:
  static constexpr int kSchemaVersion = 2;

  // Opens or creates the database at `path` (created 0600), applies migrations up to
  // kSchemaVersion, sets WAL and synchronous=FULL. Throws StoreError naming the file.
  explicit ResultStore(const std::string& path);
  ~ResultStore();
  ResultStore(const ResultStore&) = delete;
  ResultStore& operator=(const ResultStore&) = delete;

  const std::string& path() const { return path_; }
  int schema_version() const;

  // Inserts a session with status "running"; returns its id.
  std::int64_t begin_session(const SessionRecord& session);
  // Sets status (completed | aborted) and finished_utc.
  void finish_session(std::int64_t session_id, const std::string& status);
  // Marks a resumed session running again (finished_utc cleared).
  void reopen_session(std::int64_t session_id);

  // One transaction: the trial row and its frames. Returns the trial id.
  std::int64_t commit_trial(const TrialRecord& trial, const std::vector<FrameRecord>& frames);
  // The same with the settings of an adjustment trial, all in one transaction.
  std::int64_t commit_trial(const TrialRecord& trial, const std::vector<FrameRecord>& frames,
                            const std::vector<AdjustmentSetting>& adjustments);
  // Tracker samples in one transaction.
  void append_tracker_samples(std::int64_t session_id, const std::vector<TrackerSampleRecord>& samples);
  // Free-form session log line (decisions, warnings, GL info); committed immediately.
  void log_event(std::int64_t session_id, double session_time_s, const std::string& kind, const std::string& message);

  std::optional<SessionRecord> load_session(std::int64_t session_id) const;
  std::vector<SessionRecord> load_sessions() const;
  std::vector<TrialRecord> load_trials(std::int64_t session_id) const;
  std::vector<FrameRecord> load_frames(std::int64_t trial_id) const;  // in flip order
  std::vector<AdjustmentSetting> load_adjustments(std::int64_t trial_id) const;  // ordered by spot
  // Largest flip_s logged for the session (0 when none), for continuing its time line on resume.
  double last_flip_s(std::int64_t session_id) const;
  std::int64_t frame_count(std::int64_t session_id) const;

  // "ok" when the database is sound (PRAGMA integrity_check).
  std::string integrity_check() const;

  sqlite3* handle() const { return db_; }

 private:
  std::string path_;
  sqlite3* db_ = nullptr;
};

// Current UTC time as ISO 8601 with milliseconds.
std::string utc_now_iso8601();

}  // namespace glarelab

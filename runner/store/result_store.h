#pragma once
// The results database (SQLite). Contract (docs/DATABASE.md):
//  - tables sessions, trials, frames, tracker_samples, session_events, with the columns of
//    docs/DATABASE.md "Tables" (never renamed), and a schema version in PRAGMA user_version that migrations upgrade;
//  - WAL journal with synchronous=FULL; a trial and its frames are one transaction, committed
//    before the next trial's answer is taken (beside its onset, runner/session/trial_commit.cpp), so a
//    killed run loses at most the trial in progress and the one answered just before it;
//  - the database file is created with owner-only permissions (0600).
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/result_records.h"

struct sqlite3;

namespace glarelab {

class ResultStore {
 public:
  static constexpr int kSchemaVersion = kResultsSchemaVersion;

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
  // begin_session in one transaction with a count of the sessions of session.experiment already
  // in the database: nothing is written, and nothing returned, when that count is no longer
  // `earlier_sessions` (another run took the participant number it was chosen from).
  std::optional<std::int64_t> begin_session_after(const SessionRecord& session, int earlier_sessions);
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

// Throws StoreError ("SQLite: PATH: is a directory, not a database file") for a directory, which
// SQLite itself reports only as "disk I/O error".
void refuse_directory_as_database(const std::string& path);

}  // namespace glarelab

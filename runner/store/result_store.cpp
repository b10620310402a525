#include "runner/store/result_store.h"

#include <fcntl.h>
#include <sqlite3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <iterator>
#include <bit>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <system_error>
#include <thread>

#include "core/database_wait.h"
#include "runner/store/schema_migrations.h"
#include "runner/store/sqlite_statement.h"

namespace glarelab {
namespace {

using sqlite::exec;
using sqlite::fail;
using sqlite::read_user_version;
using sqlite::Statement;
using sqlite::Transaction;

// sqlite3 stores 64-bit signed integers only. A seed is any uint64, so it is stored as the
// int64 with the same bits (seeds >= 2^63 read as negative numbers in the sqlite3 shell) and
// bit-cast back on load; the round trip is exact for every value.
std::int64_t seed_to_sql(std::uint64_t seed) { return std::bit_cast<std::int64_t>(seed); }
std::uint64_t seed_from_sql(std::int64_t stored) { return std::bit_cast<std::uint64_t>(stored); }

// The file is created here, not by sqlite3_open, so that it never exists with the umask's
// default permissions: results identify participants. SQLite creates the -wal and -shm files
// with the permissions of the database file.
void create_private_file(const std::string& path) {
  const std::filesystem::path file(path);
  if (file.has_parent_path()) {
    std::error_code error;
    std::filesystem::create_directories(file.parent_path(), error);
    if (error) {
      throw StoreError("SQLite: " + path + ": creating directory " + file.parent_path().string() + ": " +
                       error.message());
    }
  }
  if (std::filesystem::exists(file)) return;
  const int fd = ::open(path.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, S_IRUSR | S_IWUSR);
  if (fd < 0) throw StoreError("SQLite: " + path + ": creating the database file: " + std::strerror(errno));
  ::close(fd);
}

SessionRecord read_session(const Statement& row) {
  SessionRecord session;
  session.id = row.int64(0);
  session.experiment = row.text(1);
  session.participant = row.text(2);
  session.seed = seed_from_sql(row.int64(3));
  session.started_utc = row.text(4);
  session.finished_utc = row.text(5);
  session.status = row.text(6);
  session.config = row.text(7);
  session.software_version = row.text(8);
  session.renderer = row.text(9);
  session.display_backend = row.text(10);
  session.clock = row.text(11);
  session.observer = row.text(12);
  return session;
}

constexpr const char* kSelectSession =
    "SELECT id, experiment, participant, seed, started_utc, finished_utc, status, config, "
    "software_version, renderer, display_backend, clock, observer FROM sessions";

// Switches the file to WAL, waiting for other connections meanwhile. On a new file the switch
// writes it, and where other processes open the same file at that moment (sessions started
// together) it can fail at once with SQLITE_BUSY ("database is locked": 15 of 1200 stores opened
// four processes at a time on new files, 33 of 800 eight at a time): SQLite does not call the
// busy handler where waiting could deadlock two connections that each hold a read lock and want
// to write (sqlite3_busy_handler's documentation), and refuses one of them. The refused switch has
// released its locks, so it is tried again until the busy timeout has passed. Once the file is in
// WAL, the switch changes nothing.
void set_wal_journal_mode(sqlite3* db, const std::string& path) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::milliseconds(kDatabaseBusyTimeoutMs);
  for (;;) {
    {
      // Finalized before the wait: a refused statement keeps nothing.
      Statement journal(db, path, "PRAGMA journal_mode=WAL", "setting journal_mode=WAL");
      if (const std::optional<bool> row = journal.step_unless_busy()) {
        const std::string mode = *row ? journal.text(0) : std::string();
        if (mode != "wal")
          throw StoreError("SQLite: " + path + ": setting journal_mode=WAL: the database stayed in mode '" + mode + "'");
        return;
      }
      if (std::chrono::steady_clock::now() >= give_up) fail(db, path, "setting journal_mode=WAL");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

}  // namespace

void refuse_directory_as_database(const std::string& path) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored))
    throw StoreError("SQLite: " + path + ": is a directory, not a database file");
}

ResultStore::ResultStore(const std::string& path) : path_(path) {
  refuse_directory_as_database(path_);
  create_private_file(path_);
  const int open_rc = sqlite3_open_v2(path_.c_str(), &db_, SQLITE_OPEN_READWRITE, nullptr);
  try {
    if (open_rc != SQLITE_OK) fail(db_, path_, "opening the database");
    // Another process (an analysis script) may hold a lock briefly; wait rather than fail.
    sqlite3_busy_timeout(db_, kDatabaseBusyTimeoutMs);

    // Reading the header first: a file that is not a database fails here (SQLITE_NOTADB), and
    // a newer schema is refused before this program changes anything in it. The version and the
    // table list are read in one read transaction, so they come from one snapshot: otherwise a
    // second glarelab creating the same new file could commit its first migration (tables and
    // version together) between the two reads, and this one would see tables without a version
    // and take the file for another program's (two sessions started together on one database).
    exec(db_, path_, "BEGIN", "starting a read transaction for the schema version");
    const int version = read_user_version(db_, path_);
    bool foreign_tables = false;
    if (version == 0) {
      // A new file has no tables. One with tables and no schema version belongs to another
      // program: adding glarelab's tables to it would mix two programs' data in one file.
      Statement tables(db_, path_, "SELECT count(*) FROM sqlite_master", "reading the table list");
      foreign_tables = tables.step() && tables.int64(0) > 0;
    }
    exec(db_, path_, "COMMIT", "ending the read transaction for the schema version");
    if (version > kSchemaVersion) {
      throw StoreError(path_ + ": schema version " + std::to_string(version) + " is newer than this glarelab (" +
                       std::to_string(kSchemaVersion) + ")");
    }
    if (version < 0) throw StoreError(path_ + ": invalid schema version " + std::to_string(version));
    if (foreign_tables)
      throw StoreError("SQLite: " + path_ + ": holds tables but no glarelab schema version: another program's "
                       "database; give glarelab a file of its own");

    set_wal_journal_mode(db_, path_);
    // FULL syncs the WAL at every commit: a committed trial survives a power cut, not only a
    // crash of this process.
    exec(db_, path_, "PRAGMA synchronous=FULL", "setting synchronous=FULL");
    for (int from = version; from < kSchemaVersion; ++from) {
      const std::string what = "migrating the schema from version " + std::to_string(from) + " to " +
                               std::to_string(from + 1);
      Transaction transaction(db_, path_, what);
      // Another connection (a second process opening the same new file) may have migrated
      // between the version read above and this write lock: read it again under the lock.
      if (read_user_version(db_, path_) > from) continue;
      exec(db_, path_, kSchemaMigrations[static_cast<std::size_t>(from)], what);
      const std::string bump = "PRAGMA user_version=" + std::to_string(from + 1);
      exec(db_, path_, bump.c_str(), what);
      transaction.commit();
    }
    // After the migrations: one that rebuilds a table (3 -> 4) drops a table that others refer
    // to, which foreign keys would refuse, and PRAGMA foreign_keys cannot be switched inside the
    // migrations' transactions; so foreign keys are switched on once the schema is current.
    exec(db_, path_, "PRAGMA foreign_keys=ON", "enabling foreign keys");
  } catch (...) {
    // The destructor does not run for a constructor that throws.
    sqlite3_close_v2(db_);
    db_ = nullptr;
    throw;
  }
}

ResultStore::~ResultStore() {
  // Closing checkpoints the WAL into the database file when this is the last connection.
  sqlite3_close_v2(db_);
}

int ResultStore::schema_version() const { return read_user_version(db_, path_); }

std::int64_t ResultStore::begin_session(const SessionRecord& session) {
  Statement insert(db_, path_,
                   "INSERT INTO sessions (experiment, participant, seed, started_utc, finished_utc, status, config, "
                   "software_version, renderer, display_backend, clock, observer) "
                   "VALUES (?1, ?2, ?3, ?4, NULL, 'running', ?5, ?6, ?7, ?8, ?9, ?10)",
                   "inserting a session");
  insert.bind(1, session.experiment);
  insert.bind(2, session.participant);
  insert.bind(3, seed_to_sql(session.seed));
  insert.bind(4, session.started_utc.empty() ? utc_now_iso8601() : session.started_utc);
  insert.bind(5, session.config);
  insert.bind(6, session.software_version);
  insert.bind(7, session.renderer);
  insert.bind(8, session.display_backend);
  insert.bind(9, session.clock);
  insert.bind(10, session.observer);
  insert.step_done();
  return sqlite3_last_insert_rowid(db_);
}

std::optional<std::int64_t> ResultStore::begin_session_after(const SessionRecord& session, int earlier_sessions) {
  Transaction transaction(db_, path_, "inserting a session");
  {
    Statement count(db_, path_, "SELECT COUNT(*) FROM sessions WHERE experiment = ?1", "counting earlier sessions");
    count.bind(1, session.experiment);
    if (!count.step() || count.int64(0) != earlier_sessions) return std::nullopt;  // rolled back
  }
  const std::int64_t session_id = begin_session(session);
  transaction.commit();
  return session_id;
}

void ResultStore::finish_session(std::int64_t session_id, const std::string& status) {
  const std::string what = "finishing session " + std::to_string(session_id);
  if (status != "completed" && status != "aborted") {
    throw StoreError("SQLite: " + path_ + ": " + what + ": status must be completed or aborted, not '" + status +
                     "'");
  }
  // A completed session is never resumed, so nothing would ever take over its lease: the lease
  // ends in the same transaction as the session, or a kill between the two would leave it behind.
  Transaction transaction(db_, path_, what);
  Statement update(db_, path_, "UPDATE sessions SET status = ?1, finished_utc = ?2 WHERE id = ?3", what);
  update.bind(1, status);
  update.bind(2, utc_now_iso8601());
  update.bind(3, session_id);
  update.step_done();
  if (sqlite3_changes(db_) != 1) throw StoreError("SQLite: " + path_ + ": " + what + ": no such session");
  if (status == "completed") {
    Statement release(db_, path_, "DELETE FROM session_owners WHERE session_id = ?1", what);
    release.bind(1, session_id);
    release.step_done();
  }
  transaction.commit();
}

void ResultStore::reopen_session(std::int64_t session_id) {
  const std::string what = "reopening session " + std::to_string(session_id);
  Statement update(db_, path_, "UPDATE sessions SET status = 'running', finished_utc = NULL WHERE id = ?1", what);
  update.bind(1, session_id);
  update.step_done();
  if (sqlite3_changes(db_) != 1) throw StoreError("SQLite: " + path_ + ": " + what + ": no such session");
}

std::int64_t ResultStore::commit_trial(const TrialRecord& trial, const std::vector<FrameRecord>& frames) {
  return commit_trial(trial, frames, {});
}

std::int64_t ResultStore::commit_trial(const TrialRecord& trial, const std::vector<FrameRecord>& frames,
                                       const std::vector<AdjustmentSetting>& adjustments) {
  const std::string what =
      "committing trial " + std::to_string(trial.trial_index) + " of session " + std::to_string(trial.session_id);
  Transaction transaction(db_, path_, what);

  Statement insert(db_, path_,
                   "INSERT INTO trials (session_id, trial_index, block, procedure, condition, intensity, response, "
                   "correct, response_time_s, onset_s, staircase, reversal, started_utc) "
                   "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13)",
                   what);
  insert.bind(1, trial.session_id);
  insert.bind(2, trial.trial_index);
  insert.bind(3, trial.block);
  insert.bind(4, trial.procedure);
  insert.bind(5, trial.condition);
  insert.bind(6, trial.intensity);
  insert.bind(7, trial.response);
  insert.bind(8, trial.correct);
  insert.bind(9, trial.response_time_s);
  insert.bind(10, trial.onset_s);
  insert.bind_text_or_null(11, trial.staircase);
  insert.bind(12, trial.reversal);
  insert.bind(13, trial.started_utc.empty() ? utc_now_iso8601() : trial.started_utc);
  insert.step_done();
  const std::int64_t trial_id = sqlite3_last_insert_rowid(db_);

  Statement frame_insert(db_, path_,
                         "INSERT INTO frames (session_id, trial_id, frame_index, scheduled_s, flip_s, dropped, "
                         "gaze_age_s) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)",
                         what + " (frames)");
  for (const FrameRecord& frame : frames) {
    frame_insert.reset();
    frame_insert.bind(1, trial.session_id);
    frame_insert.bind(2, trial_id);
    frame_insert.bind(3, frame.frame_index);
    frame_insert.bind(4, frame.scheduled_s);
    frame_insert.bind(5, frame.flip_s);
    frame_insert.bind(6, frame.dropped ? 1 : 0);
    frame_insert.bind(7, frame.gaze_age_s);
    frame_insert.step_done();
  }
  if (!adjustments.empty()) {
    Statement adjustment_insert(db_, path_, "INSERT INTO adjustments (trial_id, spot, value_cd_m2) VALUES (?1, ?2, ?3)",
                                what + " (adjustments)");
    for (const AdjustmentSetting& adjustment : adjustments) {
      adjustment_insert.reset();
      adjustment_insert.bind(1, trial_id);
      adjustment_insert.bind(2, adjustment.spot);
      adjustment_insert.bind(3, adjustment.value_cd_m2);
      adjustment_insert.step_done();
    }
  }
  transaction.commit();
  return trial_id;
}

void ResultStore::append_tracker_samples(std::int64_t session_id, const std::vector<TrackerSampleRecord>& samples) {
  if (samples.empty()) return;
  const std::string what = "appending tracker samples of session " + std::to_string(session_id);
  Transaction transaction(db_, path_, what);
  Statement insert(db_, path_,
                   "INSERT INTO tracker_samples (session_id, eye, device_time_s, session_time_s, pupil_diameter_mm, "
                   "gaze_x, gaze_y, confidence, valid) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)",
                   what);
  for (const TrackerSampleRecord& sample : samples) {
    insert.reset();
    insert.bind(1, session_id);
    insert.bind(2, sample.eye);
    insert.bind(3, sample.device_time_s);
    insert.bind(4, sample.session_time_s);
    insert.bind(5, sample.pupil_diameter_mm);
    insert.bind(6, sample.gaze_x);
    insert.bind(7, sample.gaze_y);
    insert.bind(8, sample.confidence);
    insert.bind(9, sample.valid ? 1 : 0);
    insert.step_done();
  }
  transaction.commit();
}

void ResultStore::log_event(std::int64_t session_id, double session_time_s, const std::string& kind,
                            const std::string& message) {
  Statement insert(db_, path_,
                   "INSERT INTO session_events (session_id, session_time_s, wall_utc, kind, message) "
                   "VALUES (?1, ?2, ?3, ?4, ?5)",
                   "logging a " + kind + " event of session " + std::to_string(session_id));
  insert.bind(1, session_id);
  insert.bind(2, session_time_s);
  insert.bind(3, utc_now_iso8601());
  insert.bind(4, kind);
  insert.bind(5, message);
  insert.step_done();
}

std::optional<SessionRecord> ResultStore::load_session(std::int64_t session_id) const {
  Statement select(db_, path_, (std::string(kSelectSession) + " WHERE id = ?1").c_str(),
                   "loading session " + std::to_string(session_id));
  select.bind(1, session_id);
  if (!select.step()) return std::nullopt;
  return read_session(select);
}

std::vector<SessionRecord> ResultStore::load_sessions() const {
  Statement select(db_, path_, (std::string(kSelectSession) + " ORDER BY id").c_str(), "loading sessions");
  std::vector<SessionRecord> sessions;
  while (select.step()) sessions.push_back(read_session(select));
  return sessions;
}

std::vector<TrialRecord> ResultStore::load_trials(std::int64_t session_id) const {
  Statement select(db_, path_,
                   "SELECT id, session_id, trial_index, block, procedure, condition, intensity, response, correct, "
                   "response_time_s, onset_s, staircase, reversal, started_utc FROM trials "
                   "WHERE session_id = ?1 ORDER BY trial_index",
                   "loading the trials of session " + std::to_string(session_id));
  select.bind(1, session_id);
  std::vector<TrialRecord> trials;
  while (select.step()) {
    TrialRecord trial;
    trial.id = select.int64(0);
    trial.session_id = select.int64(1);
    trial.trial_index = select.integer(2);
    trial.block = select.integer(3);
    trial.procedure = select.text(4);
    trial.condition = select.text(5);
    trial.intensity = select.optional_real(6);
    trial.response = select.text(7);
    trial.correct = select.optional_integer(8);
    trial.response_time_s = select.optional_real(9);
    trial.onset_s = select.real(10);
    trial.staircase = select.text(11);
    trial.reversal = select.optional_integer(12);
    trial.started_utc = select.text(13);
    trials.push_back(std::move(trial));
  }
  return trials;
}

std::vector<FrameRecord> ResultStore::load_frames(std::int64_t trial_id) const {
  Statement select(db_, path_,
                   "SELECT frame_index, scheduled_s, flip_s, dropped, gaze_age_s FROM frames WHERE trial_id = ?1 "
                   "ORDER BY rowid",  // flip order: a trial's other flips (frame_index < 0) surround its stimulus
                   "loading the frames of trial " + std::to_string(trial_id));
  select.bind(1, trial_id);
  std::vector<FrameRecord> frames;
  while (select.step()) {
    FrameRecord frame;
    frame.frame_index = select.integer(0);
    frame.scheduled_s = select.real(1);
    frame.flip_s = select.real(2);
    frame.dropped = select.integer(3) != 0;
    frame.gaze_age_s = select.optional_real(4);
    frames.push_back(frame);
  }
  return frames;
}

std::vector<AdjustmentSetting> ResultStore::load_adjustments(std::int64_t trial_id) const {
  Statement select(db_, path_, "SELECT spot, value_cd_m2 FROM adjustments WHERE trial_id = ?1 ORDER BY spot",
                   "loading the adjustments of trial " + std::to_string(trial_id));
  select.bind(1, trial_id);
  std::vector<AdjustmentSetting> adjustments;
  while (select.step()) adjustments.push_back({select.integer(0), select.real(1)});
  return adjustments;
}

double ResultStore::last_flip_s(std::int64_t session_id) const {
  Statement select(db_, path_, "SELECT MAX(flip_s) FROM frames WHERE session_id = ?1",
                   "reading the last flip of session " + std::to_string(session_id));
  select.bind(1, session_id);
  if (!select.step() || select.is_null(0)) return 0.0;
  return select.real(0);
}

std::int64_t ResultStore::frame_count(std::int64_t session_id) const {
  Statement select(db_, path_, "SELECT COUNT(*) FROM frames WHERE session_id = ?1",
                   "counting the frames of session " + std::to_string(session_id));
  select.bind(1, session_id);
  return select.step() ? select.int64(0) : 0;
}

std::string ResultStore::integrity_check() const {
  Statement check(db_, path_, "PRAGMA integrity_check", "checking integrity");
  // Sound databases return the single row "ok"; otherwise one row per problem.
  std::string result;
  while (check.step()) {
    if (!result.empty()) result += '\n';
    result += check.text(0);
  }
  return result;
}

std::string utc_now_iso8601() {
  using namespace std::chrono;
  const auto now = floor<milliseconds>(system_clock::now());
  const std::time_t seconds = system_clock::to_time_t(floor<std::chrono::seconds>(now));
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  const auto millis = (now.time_since_epoch() % std::chrono::seconds(1)).count();
  char text[32];
  const std::size_t length = std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &utc);
  std::snprintf(text + length, sizeof text - length, ".%03dZ", static_cast<int>(millis));
  return text;
}

}  // namespace glarelab

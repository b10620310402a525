#include "analysis/loaded_database.h"

#include <sqlite3.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <unordered_map>
#include <unordered_set>
#include <stdexcept>

#include "core/database_wait.h"
#include "core/text_limits.h"

namespace glarelab::analysis {
namespace {

// Finalizes on every path.
struct StatementGuard {
  sqlite3_stmt* stmt;
  ~StatementGuard() { sqlite3_finalize(stmt); }
};

// A read-only connection that names the file in every error.
class ReadOnlyDatabase {
 public:
  explicit ReadOnlyDatabase(const std::string& path) : path_(path) {
    if (!std::filesystem::exists(path)) throw StoreError("analysis: " + path + ": no such file");
    if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
      const std::string message = db_ != nullptr ? sqlite3_errmsg(db_) : "out of memory";
      sqlite3_close(db_);
      throw StoreError("analysis: " + path + ": cannot open: " + message);
    }
    // A session writing the file holds its lock for moments (a commit, the checkpoint when its
    // last connection closes; the whole file where another program asked for it alone): the
    // reads wait for it, as the store's writes do, rather than fail with "database is locked".
    sqlite3_busy_timeout(db_, kDatabaseBusyTimeoutMs);
  }
  ~ReadOnlyDatabase() { sqlite3_close(db_); }
  ReadOnlyDatabase(const ReadOnlyDatabase&) = delete;
  ReadOnlyDatabase& operator=(const ReadOnlyDatabase&) = delete;

  sqlite3_stmt* prepare(const std::string& sql) const {
    sqlite3_stmt* stmt = nullptr;
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &stmt, nullptr) != SQLITE_OK) {
      throw StoreError("analysis: " + path_ + ": " + sqlite3_errmsg(db_) + " in: " + sql);
    }
    return stmt;
  }
  bool step(sqlite3_stmt* stmt) const {
    const int rc = sqlite3_step(stmt);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    throw StoreError("analysis: " + path_ + ": " + sqlite3_errmsg(db_));
  }
  // Column names of `table`; empty when the table does not exist.
  std::set<std::string> columns(const std::string& table) const {
    std::set<std::string> names;
    // Finalized also when step throws (a file that is not a database fails there): an unfinalized
    // statement makes sqlite3_close fail and the connection leak.
    const StatementGuard guard{prepare("PRAGMA table_info(" + table + ")")};
    while (step(guard.stmt)) names.insert(reinterpret_cast<const char*>(sqlite3_column_text(guard.stmt, 1)));
    return names;
  }
  void exec(const char* sql) const {
    if (sqlite3_exec(db_, sql, nullptr, nullptr, nullptr) != SQLITE_OK) {
      throw StoreError("analysis: " + path_ + ": " + sqlite3_errmsg(db_) + " in: " + sql);
    }
  }
  int user_version() const {
    const StatementGuard guard{prepare("PRAGMA user_version")};
    return step(guard.stmt) ? sqlite3_column_int(guard.stmt, 0) : 0;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  sqlite3* db_ = nullptr;
};

std::string text(sqlite3_stmt* stmt, int column) {
  const unsigned char* value = sqlite3_column_text(stmt, column);
  return value != nullptr ? reinterpret_cast<const char*>(value) : std::string();
}
std::optional<double> optional_real(sqlite3_stmt* stmt, int column) {
  if (sqlite3_column_type(stmt, column) == SQLITE_NULL) return std::nullopt;
  return sqlite3_column_double(stmt, column);
}
std::optional<int> optional_int(sqlite3_stmt* stmt, int column) {
  if (sqlite3_column_type(stmt, column) == SQLITE_NULL) return std::nullopt;
  return sqlite3_column_int(stmt, column);
}

// "col" when the table has it, else "NULL": older schema versions lack the non-contract columns.
std::string column_or_null(const std::set<std::string>& have, const std::string& name) {
  return have.count(name) != 0 ? name : "NULL";
}

void require_columns(const ReadOnlyDatabase& db, const std::string& table, const std::set<std::string>& have,
                     const std::vector<std::string>& needed) {
  for (const std::string& name : needed) {
    if (have.count(name) == 0) {
      throw StoreError("analysis: " + db.path() + ": table " + table + " lacks the contract column '" + name + "'");
    }
  }
}

// Where each trial id of one file landed in LoadedData: (session index, trial index).
using TrialPlaces = std::unordered_map<std::int64_t, std::pair<std::size_t, std::size_t>>;

// Appends the file's sessions to data.sessions; returns each session id's index there.
std::map<std::int64_t, std::size_t> load_sessions(const ReadOnlyDatabase& db, const std::set<std::string>& columns,
                                                  LoadedData& data) {
  const std::size_t first = data.sessions.size();
  StatementGuard query{db.prepare(
      "SELECT id, experiment, participant, seed, started_utc, finished_utc, status, config, software_version, "
      "renderer, " +
      column_or_null(columns, "display_backend") + ", " + column_or_null(columns, "clock") + ", " +
      column_or_null(columns, "observer") + " FROM sessions ORDER BY id")};
  while (db.step(query.stmt)) {
    LoadedSession session;
    session.database = db.path();
    SessionRecord& r = session.record;
    r.id = sqlite3_column_int64(query.stmt, 0);
    r.experiment = text(query.stmt, 1);
    r.participant = text(query.stmt, 2);
    r.seed = std::bit_cast<std::uint64_t>(static_cast<std::int64_t>(sqlite3_column_int64(query.stmt, 3)));
    r.started_utc = text(query.stmt, 4);
    r.finished_utc = text(query.stmt, 5);
    r.status = text(query.stmt, 6);
    r.config = text(query.stmt, 7);
    r.software_version = text(query.stmt, 8);
    r.renderer = text(query.stmt, 9);
    r.display_backend = text(query.stmt, 10);
    r.clock = text(query.stmt, 11);
    r.observer = text(query.stmt, 12);
    data.sessions.push_back(std::move(session));
  }
  std::map<std::int64_t, std::size_t> session_at;
  for (std::size_t i = first; i < data.sessions.size(); ++i) session_at[data.sessions[i].record.id] = i;
  return session_at;
}

// Appends each trial to its session (a trial without its session is not analysable and is left
// out); returns where each landed.
TrialPlaces load_trials(const ReadOnlyDatabase& db, const std::set<std::string>& columns,
                        const std::map<std::int64_t, std::size_t>& session_at, LoadedData& data) {
  TrialPlaces trial_at;
  // An experiment repeats a few condition texts over thousands of trials: each distinct text is
  // parsed once (nullopt: not a JSON object).
  std::unordered_map<std::string, std::optional<ConditionFields>> parsed_conditions;
  StatementGuard query{db.prepare(
      "SELECT id, session_id, trial_index, block, procedure, condition, intensity, response, correct, "
      "response_time_s, onset_s, staircase, reversal, " +
      column_or_null(columns, "started_utc") + " FROM trials ORDER BY session_id, trial_index")};
  int unreadable = 0;
  int not_finite = 0;
  while (db.step(query.stmt)) {
    LoadedTrial trial;
    TrialRecord& r = trial.record;
    r.id = sqlite3_column_int64(query.stmt, 0);
    r.session_id = sqlite3_column_int64(query.stmt, 1);
    r.trial_index = sqlite3_column_int(query.stmt, 2);
    r.block = sqlite3_column_int(query.stmt, 3);
    r.procedure = text(query.stmt, 4);
    r.condition = text(query.stmt, 5);
    r.intensity = optional_real(query.stmt, 6);
    r.response = text(query.stmt, 7);
    r.correct = optional_int(query.stmt, 8);
    r.response_time_s = optional_real(query.stmt, 9);
    r.onset_s = sqlite3_column_double(query.stmt, 10);
    r.staircase = text(query.stmt, 11);
    r.reversal = optional_int(query.stmt, 12);
    r.started_utc = text(query.stmt, 13);
    // A time or an intensity of +-inf or NaN is no measurement (SQLite stores them; glarelab never
    // writes them): read as empty and counted, so no statistic or histogram bin is computed from it.
    for (std::optional<double>* value : {&r.response_time_s, &r.intensity}) {
      if (*value && !std::isfinite(**value)) {
        value->reset();
        ++not_finite;
      }
    }
    auto [parsed, first_seen] = parsed_conditions.try_emplace(r.condition);
    if (first_seen) {
      try {
        parsed->second = parse_condition_json(r.condition);
      } catch (const std::invalid_argument&) {
        parsed->second = std::nullopt;
      }
    }
    if (parsed->second) {
      trial.condition = *parsed->second;
    } else {
      ++unreadable;
      trial.condition = {{"name", r.condition}};
    }
    const auto owner = session_at.find(r.session_id);
    if (owner == session_at.end()) continue;  // a trial without its session is not analysable
    auto& trials = data.sessions[owner->second].trials;
    trial_at[r.id] = {owner->second, trials.size()};
    trials.push_back(std::move(trial));
  }
  if (unreadable > 0) {
    data.notes.push_back(db.path() + ": " + std::to_string(unreadable) +
                         " trial(s) with a condition that is not a JSON object: used as the condition name");
  }
  if (not_finite > 0) {
    data.notes.push_back(db.path() + ": " + std::to_string(not_finite) +
                         " response time(s) or intensit(ies) that are not finite numbers: read as empty");
  }
  return trial_at;
}

void load_frames(const ReadOnlyDatabase& db, const std::set<std::string>& columns, const TrialPlaces& trial_at,
                 LoadedData& data) {
  StatementGuard query{db.prepare("SELECT trial_id, frame_index, scheduled_s, flip_s, dropped, " +
                                  column_or_null(columns, "gaze_age_s") + " FROM frames ORDER BY trial_id, rowid")};
  while (db.step(query.stmt)) {
    const auto found = trial_at.find(sqlite3_column_int64(query.stmt, 0));
    if (found == trial_at.end()) continue;
    FrameRecord frame;
    frame.frame_index = sqlite3_column_int(query.stmt, 1);
    frame.scheduled_s = sqlite3_column_double(query.stmt, 2);
    frame.flip_s = sqlite3_column_double(query.stmt, 3);
    frame.dropped = sqlite3_column_int(query.stmt, 4) != 0;
    frame.gaze_age_s = optional_real(query.stmt, 5);
    data.sessions[found->second.first].trials[found->second.second].frames.push_back(frame);
  }
}

void load_tracker_samples(const ReadOnlyDatabase& db, const std::map<std::int64_t, std::size_t>& session_at,
                          LoadedData& data) {
  StatementGuard query{db.prepare(
      "SELECT session_id, eye, device_time_s, session_time_s, pupil_diameter_mm, gaze_x, gaze_y, confidence, valid "
      "FROM tracker_samples ORDER BY session_id, session_time_s, eye")};
  while (db.step(query.stmt)) {
    const auto owner = session_at.find(sqlite3_column_int64(query.stmt, 0));
    if (owner == session_at.end()) continue;
    TrackerSampleRecord sample;
    sample.eye = sqlite3_column_int(query.stmt, 1);
    sample.device_time_s = sqlite3_column_double(query.stmt, 2);
    sample.session_time_s = sqlite3_column_double(query.stmt, 3);
    sample.pupil_diameter_mm = optional_real(query.stmt, 4);
    sample.gaze_x = optional_real(query.stmt, 5);
    sample.gaze_y = optional_real(query.stmt, 6);
    sample.confidence = sqlite3_column_double(query.stmt, 7);
    sample.valid = sqlite3_column_int(query.stmt, 8) != 0;
    data.sessions[owner->second].tracker_samples.push_back(sample);
  }
}

void load_adjustments(const ReadOnlyDatabase& db, const TrialPlaces& trial_at, LoadedData& data) {
  StatementGuard query{db.prepare("SELECT trial_id, spot, value_cd_m2 FROM adjustments ORDER BY trial_id, spot")};
  while (db.step(query.stmt)) {
    const auto found = trial_at.find(sqlite3_column_int64(query.stmt, 0));
    if (found == trial_at.end()) continue;
    data.sessions[found->second.first].trials[found->second.second].adjustments.push_back(
        {sqlite3_column_int(query.stmt, 1), sqlite3_column_double(query.stmt, 2)});
  }
}

void load_one(const std::string& path, LoadedData& data) {
  const ReadOnlyDatabase db(path);
  // One read transaction: every table is read from the same snapshot, even while a runner is
  // still appending to the file (closing the connection ends it).
  db.exec("BEGIN");
  const int version = db.user_version();
  if (version > kResultsSchemaVersion) {
    throw StoreError("analysis: " + path + ": schema version " + std::to_string(version) +
                     " is newer than this glarelab reads (" + std::to_string(kResultsSchemaVersion) +
                     "): update glarelab");
  }
  const auto session_columns = db.columns("sessions");
  const auto trial_columns = db.columns("trials");
  if (session_columns.empty() || trial_columns.empty()) {
    throw StoreError("analysis: " + path + ": not a glarelab results database (no sessions or trials table)");
  }
  require_columns(db, "sessions", session_columns,
                  {"id", "experiment", "participant", "seed", "started_utc", "finished_utc", "status", "config",
                   "software_version", "renderer"});
  require_columns(db, "trials", trial_columns,
                  {"id", "session_id", "trial_index", "block", "procedure", "condition", "intensity", "response",
                   "correct", "response_time_s", "onset_s", "staircase", "reversal"});
  if (version < kResultsSchemaVersion) {
    data.notes.push_back(path + ": schema version " + std::to_string(version) + " is older than the current " +
                         std::to_string(kResultsSchemaVersion) +
                         "; loaded the contract columns it has (columns added later read as empty)");
  }
  const auto frame_columns = db.columns("frames");
  const auto tracker_columns = db.columns("tracker_samples");
  const bool have_adjustments = !db.columns("adjustments").empty();
  if (frame_columns.empty()) data.notes.push_back(path + ": no frames table: timing quality not available");
  if (tracker_columns.empty()) data.notes.push_back(path + ": no tracker_samples table");

  const std::map<std::int64_t, std::size_t> session_at = load_sessions(db, session_columns, data);
  const TrialPlaces trial_at = load_trials(db, trial_columns, session_at, data);
  if (!frame_columns.empty()) load_frames(db, frame_columns, trial_at, data);
  if (!tracker_columns.empty()) load_tracker_samples(db, session_at, data);
  if (have_adjustments) load_adjustments(db, trial_at, data);
}

}  // namespace

const std::string* LoadedTrial::condition_value(const std::string& key) const {
  for (const auto& [name, value] : condition) {
    if (name == key) return &value;
  }
  return nullptr;
}

ConditionFields parse_condition_json(const std::string& text) {
  // nlohmann::ordered_json keeps keys in a vector searched on every insert (quadratic: 200k keys
  // took minutes), so the object is parsed into the tree-backed json and the order of the top
  // level's keys is taken from the parser's key events. The depth is bounded in the same events:
  // dump() below recurses once per level.
  std::vector<std::string> order;
  std::unordered_set<std::string> seen;
  const nlohmann::json::parser_callback_t track = [&](int depth, nlohmann::json::parse_event_t event,
                                                      nlohmann::json& parsed) {
    // `depth` counts the levels open before this event: opening one more must stay within the bound.
    const bool opens = event == nlohmann::json::parse_event_t::object_start ||
                       event == nlohmann::json::parse_event_t::array_start;
    if (opens && depth >= kMaxJsonNesting)
      throw std::invalid_argument("condition is nested deeper than " + std::to_string(kMaxJsonNesting) + " levels");
    if (event == nlohmann::json::parse_event_t::key && depth == 1) {
      std::string key = parsed.get<std::string>();
      if (seen.insert(key).second) order.push_back(std::move(key));  // a repeated key keeps its first place
    }
    return true;
  };
  nlohmann::json parsed;
  try {
    parsed = nlohmann::json::parse(text, track);
  } catch (const nlohmann::json::exception& error) {
    throw std::invalid_argument(std::string("condition is not JSON: ") + error.what());
  }
  if (!parsed.is_object()) throw std::invalid_argument("condition is not a JSON object");
  ConditionFields fields;
  fields.reserve(order.size());
  for (const std::string& key : order) {
    const nlohmann::json& value = parsed.at(key);
    fields.emplace_back(key, value.is_string() ? value.get<std::string>() : value.dump());
  }
  return fields;
}

LoadedData load_databases(const std::vector<std::string>& paths) {
  LoadedData data;
  for (const std::string& path : paths) load_one(path, data);
  for (std::size_t i = 0; i < data.sessions.size(); ++i) {
    LoadedSession& session = data.sessions[i];
    session.label = session.record.participant + " (" +
                    (paths.size() > 1 ? std::filesystem::path(session.database).filename().string() + "#" : "#") +
                    std::to_string(session.record.id) + ")";
  }
  return data;
}

}  // namespace glarelab::analysis

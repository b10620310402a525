#include "runner/session/participant_number.h"

#include <sqlite3.h>

#include <filesystem>

#include "runner/store/result_store.h"

namespace glarelab {

int count_sessions(const std::string& db_path, const std::string& experiment_name) {
  std::error_code error;
  if (!std::filesystem::exists(db_path, error)) return 0;
  refuse_directory_as_database(db_path);
  // Read-only: a session writes nothing before its experiment, scenes and display are valid.
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(db_path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
    const std::string message = db != nullptr ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    throw StoreError("SQLite: " + db_path + ": cannot be read to count earlier sessions: " + message);
  }
  sqlite3_stmt* statement = nullptr;
  int count = 0;
  // A database without a sessions table (empty file) has no earlier sessions.
  if (sqlite3_prepare_v2(db, "SELECT COUNT(*) FROM sessions WHERE experiment = ?1", -1, &statement, nullptr) ==
      SQLITE_OK) {
    sqlite3_bind_text(statement, 1, experiment_name.c_str(), -1, SQLITE_TRANSIENT);
    if (sqlite3_step(statement) == SQLITE_ROW) count = sqlite3_column_int(statement, 0);
  }
  sqlite3_finalize(statement);
  sqlite3_close(db);
  return count;
}

ParticipantNumber choose_participant_number(const std::optional<int>& from_option,
                                            const std::optional<int>& from_file, const std::string& db_path,
                                            const std::string& experiment_name) {
  if (from_option) return {*from_option, "from --participant-number", std::nullopt};
  if (from_file) return {*from_file, "from the experiment file ([procedure] participant_number)", std::nullopt};
  const int earlier = count_sessions(db_path, experiment_name);
  return {earlier + 1, "1 + " + std::to_string(earlier) + " earlier session(s) of '" + experiment_name + "' in " + db_path,
          earlier};
}

}  // namespace glarelab

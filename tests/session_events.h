#pragma once
// The messages of one kind of session event in a results database, in the order they were logged.
#include <sqlite3.h>

#include <string>
#include <vector>

#include "runner/store/result_store.h"

namespace glarelab::test {

inline std::vector<std::string> session_event_messages(const ResultStore& store, const std::string& kind) {
  std::vector<std::string> messages;
  sqlite3_stmt* statement = nullptr;
  if (sqlite3_prepare_v2(store.handle(), "SELECT message FROM session_events WHERE kind = ?1 ORDER BY id", -1, &statement,
                         nullptr) != SQLITE_OK)
    return messages;
  sqlite3_bind_text(statement, 1, kind.c_str(), -1, SQLITE_TRANSIENT);
  while (sqlite3_step(statement) == SQLITE_ROW)
    messages.emplace_back(reinterpret_cast<const char*>(sqlite3_column_text(statement, 0)));
  sqlite3_finalize(statement);
  return messages;
}

inline std::vector<std::string> session_event_messages(const std::string& db_path, const std::string& kind) {
  const ResultStore store(db_path);
  return session_event_messages(store, kind);
}

}  // namespace glarelab::test

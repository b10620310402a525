#pragma once
// How long a results-database connection waits for another connection's lock before a statement
// fails with "database is locked": the store's writes (runner/store), its lock-wait handler's
// return to the plain timeout (runner/store/lock_wait.h), the analysis's read-only connection
// (analysis/loaded_database.cpp) and the tracker replay's (runner/tracker/replay_tracker.cpp).
// Locks are held for moments (a commit, the checkpoint when a session's last connection closes, a
// new file's switch to WAL); five seconds outlasts those on a stalled machine while a lock held on
// purpose by another program is still reported within a few seconds (docs/HARDENING.md).
namespace glarelab {

inline constexpr int kDatabaseBusyTimeoutMs = 5000;

}  // namespace glarelab

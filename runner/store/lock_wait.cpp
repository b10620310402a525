#include "runner/store/lock_wait.h"

#include <algorithm>
#include <string>
#include <thread>

#include "core/database_wait.h"

namespace glarelab {

LockWait::LockWait(sqlite3* db, KeepWaiting keep_waiting) : db_(db), keep_waiting_(std::move(keep_waiting)) {
  sqlite3_busy_handler(db_, &LockWait::on_busy, this);
}

LockWait::~LockWait() { sqlite3_busy_timeout(db_, kDatabaseBusyTimeoutMs); }

// SQLite calls this each time a statement finds the lock held; `count` restarts at 0 for every new
// wait. Returning 0 gives up (the statement fails with SQLITE_BUSY), anything else tries again.
std::string LockWait::announcement(double waited_s) {
  return "waiting for the database: another process has held its lock for " +
         std::to_string(static_cast<int>(waited_s)) +
         " s (the trial waits in memory; Ctrl-C ends the session, keeping its trials)\n";
}

int LockWait::on_busy(void* self_pointer, int count) {
  LockWait& self = *static_cast<LockWait*>(self_pointer);
  const auto now = std::chrono::steady_clock::now();
  if (count == 0) {
    self.since_ = now;
    self.counted_ = false;
  }
  const double waited_s = std::chrono::duration<double>(now - self.since_).count();
  self.longest_wait_s_ = std::max(self.longest_wait_s_, waited_s);
  if (waited_s >= 1.0) {
    if (!self.counted_) ++self.waits_;
    self.counted_ = true;
    if (!self.keep_waiting_(waited_s)) return 0;
  }
  // Short sleeps first (most locks are a reader's moment), then 20 ms: the lock is seen free
  // within a frame or so of its release.
  std::this_thread::sleep_for(std::chrono::milliseconds(count < 20 ? 2 : 20));
  return 1;
}

}  // namespace glarelab

#pragma once
// How a live session's store waits for a lock that another process holds (an analysis, the sqlite3
// shell, a backup). By default a write fails after 5 s (ResultStore's busy timeout), which would
// end a session because somebody looked at its database. While a LockWait lives, a write waits as
// long as the lock is held, asking `keep_waiting` now and then whether to go on (the session says
// no once Ctrl-C was pressed): the trial waits in memory, nothing is lost, and the session's
// contract holds (each trial committed before the next one's answer is taken).
#include <sqlite3.h>

#include <chrono>
#include <functional>
#include <string>

namespace glarelab {

class LockWait {
 public:
  using KeepWaiting = std::function<bool(double waited_s)>;
  LockWait(sqlite3* db, KeepWaiting keep_waiting);
  // Back to the store's default busy timeout.
  ~LockWait();
  LockWait(const LockWait&) = delete;
  LockWait& operator=(const LockWait&) = delete;

  int waits() const { return waits_; }  // writes that found the lock held for over a second
  double longest_wait_s() const { return longest_wait_s_; }
  // The line a live session prints every 5 s of a wait.
  static std::string announcement(double waited_s);

 private:
  static int on_busy(void* self, int count);

  sqlite3* db_;
  KeepWaiting keep_waiting_;
  std::chrono::steady_clock::time_point since_;
  int waits_ = 0;
  bool counted_ = false;
  double longest_wait_s_ = 0.0;
};

}  // namespace glarelab

#pragma once
// Writes tracker samples, blinks and connection notices to the results database from a thread of
// its own, on a SQLite connection of its own, in batched commits (at most one every
// commit_period_s). The frame loop only appends to an in-memory queue, so a slow disk or a
// commit_trial holding the write lock never delays a frame: WAL lets this writer wait (busy
// timeout) while readers and the other writer carry on.
#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include "runner/tracker/tracker_source.h"

namespace glarelab {

class TrackerLogger {
 public:
  // Opens its own connection to `db_path` (throws StoreError when it cannot).
  TrackerLogger(const std::string& db_path, std::int64_t session_id, double commit_period_s = 0.25);
  ~TrackerLogger();
  TrackerLogger(const TrackerLogger&) = delete;
  TrackerLogger& operator=(const TrackerLogger&) = delete;

  // Never blocks beyond a short mutex: the batch is written later by the logger's thread.
  void enqueue(TrackerBatch&& batch) { queue_.push(std::move(batch)); }
  // Writes everything still queued and joins the thread. Throws StoreError if a batch could not
  // be written (after retries). Idempotent.
  void finish();

  std::int64_t samples_written() const { return samples_written_; }

 private:
  void run();

  std::string db_path_;
  std::int64_t session_id_;
  double commit_period_s_;
  TrackerQueue queue_;
  std::thread thread_;
  std::atomic<std::int64_t> samples_written_{0};
  std::string error_;  // set by the thread, read after join
  bool finished_ = false;
};

}  // namespace glarelab

// Committing a trial: its row (scored outcome, response, onset), its adjustment settings and every
// flip it showed go to the store in one transaction, then its trial_phases event. The commit runs
// on a thread of its own, on a second connection to the database, beside the next trial's
// inter-trial interval and onset: SQLite's synced writes of 30 flips took 5 to 100 ms on a disk
// other programs use, between the trial's last flip and the next onset, and made that onset late
// ("recording the trial", docs/PERFORMANCE.md). It is finished before the next answer is taken
// (finish_commit: collect_response, a key that answers in the timed sequence), before the session
// ends or stops, and before the run's progress says the trial is in: a SIGKILL before then loses
// only a trial that nothing has said was recorded, and a resumed session shows it again. The
// trial's own events (its trial_preparation, dropped_frame and glare events) go with it, written
// before its row: each is a synced write that, on the display's thread, would fall between flips.
#include <sqlite3.h>

#include <chrono>
#include <exception>
#include <future>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "core/clock.h"
#include "runner/session/interrupt.h"
#include "runner/session/session_loop.h"
#include "runner/session/trial_record.h"
#include "runner/session/trial_schedule.h"
#include "runner/store/lock_wait.h"

namespace glarelab {

void SessionLoop::commit(const TrialPlan& plan, const TrialRun& run, const TrialOutcome& outcome,
                         std::string progress_line, std::ostream& progress) {
  finish_commit();  // one trial at a time, in order
  const TrialRecord record = trial_record(session_id_, plan, outcome, run.response->response_time_s, run.onset_s,
                                          utc_now_iso8601());
  std::vector<AdjustmentSetting> adjustments = adjustment_settings(outcome);
  std::string phases = describe_trial_phases(plan.trial_index, run.phases);
  const double phases_s = clock_.now_s();
  std::vector<HeldEvent> events = std::move(events_with_commit_);
  events_with_commit_.clear();
  // An in-memory database has no second connection: committed here, as before.
  if (store_.path().empty() || store_.path() == ":memory:" || store_.path().rfind("file:", 0) == 0) {
    for (const HeldEvent& event : events) store_.log_event(session_id_, event.at_s, event.kind, event.message);
    store_.commit_trial(record, run.frames, adjustments);
    store_.log_event(session_id_, phases_s, "trial_phases", phases);
    progress << progress_line << std::flush;
    ++commits_at_once_;
    return;
  }
  ++commits_beside_;
  if (!commit_store_) {
    commit_store_ = std::make_unique<ResultStore>(store_.path());
    // As the session's own connection: a lock another process holds is waited out, not a failure
    // (runner/store/lock_wait.h), and said every 5 s by finish_commit; Ctrl-C ends the wait.
    commit_lock_wait_ = std::make_unique<LockWait>(commit_store_->handle(), [this](double waited_s) {
      commit_waited_s_ = waited_s;
      return !interrupt_requested();
    });
  }
  pending_progress_ = std::move(progress_line);
  pending_progress_stream_ = &progress;
  std::promise<void> finished;
  commit_finished_ = finished.get_future();
  committer_ = std::thread([this, record, frames = run.frames, adjustments = std::move(adjustments),
                            phases = std::move(phases), phases_s, events = std::move(events),
                            finished = std::move(finished)]() mutable {
    struct Finished {  // however the commit ends
      std::promise<void>& promise;
      std::atomic<double>& waited_s;
      ~Finished() {
        waited_s = 0.0;
        promise.set_value();
      }
    } on_end{finished, commit_waited_s_};
    try {
      for (const HeldEvent& event : events)
        commit_store_->log_event(session_id_, event.at_s, event.kind, event.message);
      commit_store_->commit_trial(record, frames, adjustments);
      commit_store_->log_event(session_id_, phases_s, "trial_phases", phases);
    } catch (...) {
      commit_error_ = std::current_exception();
    }
  });
}

void SessionLoop::finish_commit(bool write_held_events) {
  if (write_held_events) {
    for (const HeldEvent& event : events_with_commit_) store_.log_event(session_id_, event.at_s, event.kind, event.message);
    events_with_commit_.clear();
  }
  if (committer_.joinable()) {
    // A commit held up by another process's lock is said as the session's own writes are.
    double announced_s = 0.0;
    while (commit_finished_.wait_for(std::chrono::milliseconds(100)) != std::future_status::ready) {
      const double waited_s = commit_waited_s_;
      if (waited_s >= announced_s + 5.0 && pending_progress_stream_ != nullptr) {
        announced_s = waited_s;
        *pending_progress_stream_ << LockWait::announcement(waited_s) << std::flush;
      }
    }
    committer_.join();
    if (commit_error_) {
      const std::exception_ptr error = commit_error_;
      commit_error_ = nullptr;
      pending_progress_.clear();
      std::rethrow_exception(error);
    }
    if (pending_progress_stream_ != nullptr) *pending_progress_stream_ << pending_progress_ << std::flush;
    pending_progress_.clear();
  }
  // The session's end: its saved frames are on disk before it reports (a failed write aborts it).
  if (write_held_events && frame_writer_) frame_writer_->finish();
}

std::string SessionLoop::commit_summary() const {
  return std::to_string(commits_beside_) + " trial(s) committed on a connection of their own beside the next trial's " +
         "start, each finished before the next answer was taken; " + std::to_string(commits_at_once_) +
         " committed at once (an in-memory database)";
}

}  // namespace glarelab

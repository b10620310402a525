#include "runner/tracker/tracker_logger.h"

#include <chrono>

#include "runner/store/result_store.h"

namespace glarelab {

namespace {

TrackerSampleRecord to_record(const TrackerSample& sample) {
  TrackerSampleRecord record;
  record.eye = sample.eye;
  record.device_time_s = sample.device_time_s;
  record.session_time_s = sample.session_time_s;
  // A blink or lost pupil is reported with diameter 0: stored as NULL (no measurement), never 0 mm.
  if (sample.pupil_diameter_mm > 0.0) record.pupil_diameter_mm = sample.pupil_diameter_mm;
  if (sample.has_gaze()) {
    record.gaze_x = sample.gaze_x;
    record.gaze_y = sample.gaze_y;
  }
  record.confidence = sample.confidence;
  record.valid = sample.valid;
  return record;
}

}  // namespace

TrackerLogger::TrackerLogger(const std::string& db_path, std::int64_t session_id, double commit_period_s)
    : db_path_(db_path), session_id_(session_id), commit_period_s_(commit_period_s) {
  // Fail here, on the caller's thread, when the database cannot be opened at all.
  { const ResultStore probe(db_path_); }
  thread_ = std::thread([this] { run(); });
}

TrackerLogger::~TrackerLogger() {
  try {
    finish();
  } catch (...) {
    // A destructor must not throw; finish() is called explicitly where errors matter.
  }
}

void TrackerLogger::finish() {
  if (finished_) return;
  finished_ = true;
  queue_.close();
  if (thread_.joinable()) thread_.join();
  if (!error_.empty()) throw StoreError(error_);
}

void TrackerLogger::run() {
  try {
    ResultStore store(db_path_);
    TrackerBatch pending;
    auto last_commit = std::chrono::steady_clock::now();
    const auto period = std::chrono::duration<double>(commit_period_s_);
    while (true) {
      pending.append(queue_.wait_and_take(commit_period_s_));
      const bool closing = queue_.closed();
      if (closing) pending.append(queue_.take_all());
      if (!closing && std::chrono::steady_clock::now() - last_commit < period) continue;
      if (!pending.empty()) {
        // SQLITE_BUSY beyond the store's busy timeout (5 s) is retried a few times before giving up:
        // the batch stays in memory meanwhile.
        // Each part is its own commit; a retry resumes after the parts already written, so nothing
        // is stored twice.
        bool samples_done = false;
        std::size_t blinks_done = 0;
        std::size_t notices_done = 0;
        for (int attempt = 0;; ++attempt) {
          try {
            if (!samples_done) {
              std::vector<TrackerSampleRecord> records;
              records.reserve(pending.samples.size());
              for (const TrackerSample& sample : pending.samples) records.push_back(to_record(sample));
              store.append_tracker_samples(session_id_, records);
              samples_done = true;
            }
            for (; blinks_done < pending.blinks.size(); ++blinks_done) {
              const BlinkEvent& blink = pending.blinks[blinks_done];
              store.log_event(session_id_, blink.session_time_s, blink.onset ? "blink_onset" : "blink_offset",
                              "tracker blink, confidence " + std::to_string(blink.confidence));
            }
            for (; notices_done < pending.notices.size(); ++notices_done) {
              const TrackerNotice& notice = pending.notices[notices_done];
              store.log_event(session_id_, notice.session_time_s, notice.kind, notice.message);
            }
            break;
          } catch (const StoreError&) {
            if (attempt >= 3) throw;
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
          }
        }
        samples_written_ += static_cast<std::int64_t>(pending.samples.size());
        pending = TrackerBatch{};
      }
      last_commit = std::chrono::steady_clock::now();
      if (closing) break;
    }
  } catch (const std::exception& error) {
    error_ = std::string("tracker logger: ") + error.what();
  }
}

}  // namespace glarelab

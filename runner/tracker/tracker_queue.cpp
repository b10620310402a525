#include <chrono>
#include <iterator>

#include "runner/tracker/tracker_source.h"

namespace glarelab {

void TrackerBatch::append(TrackerBatch&& other) {
  samples.insert(samples.end(), std::make_move_iterator(other.samples.begin()),
                 std::make_move_iterator(other.samples.end()));
  blinks.insert(blinks.end(), other.blinks.begin(), other.blinks.end());
  notices.insert(notices.end(), std::make_move_iterator(other.notices.begin()),
                 std::make_move_iterator(other.notices.end()));
}

void TrackerQueue::push(TrackerBatch&& batch) {
  if (batch.empty()) return;
  {
    const std::lock_guard lock(mutex_);
    pending_.append(std::move(batch));
  }
  ready_.notify_one();
}

TrackerBatch TrackerQueue::take_all() {
  const std::lock_guard lock(mutex_);
  TrackerBatch out;
  std::swap(out, pending_);
  return out;
}

TrackerBatch TrackerQueue::wait_and_take(double timeout_s) {
  std::unique_lock lock(mutex_);
  ready_.wait_for(lock, std::chrono::duration<double>(timeout_s), [this] { return closed_ || !pending_.empty(); });
  TrackerBatch out;
  std::swap(out, pending_);
  return out;
}

void TrackerQueue::close() {
  {
    const std::lock_guard lock(mutex_);
    closed_ = true;
  }
  ready_.notify_all();
}

bool TrackerQueue::closed() const {
  const std::lock_guard lock(mutex_);
  return closed_;
}

}  // namespace glarelab

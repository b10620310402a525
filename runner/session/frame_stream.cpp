// Glare frames handed from the worker to the display's thread (runner/session/frame_stream.h).
#include "runner/session/frame_stream.h"

#include <algorithm>
#include <numeric>

namespace glarelab {

void FrameStream::begin(const std::vector<int>& frames_per_interval) {
  {
    const std::lock_guard lock(mutex_);
    frames_.clear();
    for (const int frames : frames_per_interval)
      frames_.emplace_back(static_cast<std::size_t>(std::max(0, frames)), nullptr);
    published_.assign(frames_per_interval.size(), 0);
    total_ = 0;
    for (const auto& interval : frames_) total_ += static_cast<int>(interval.size());
    begun_ = true;
  }
  changed_.notify_all();
}

void FrameStream::publish(int interval, int k, const GlaredRegion* frame, double compute_s) {
  {
    const std::lock_guard lock(mutex_);
    auto& frames = frames_.at(static_cast<std::size_t>(interval));
    frames.at(static_cast<std::size_t>(k)) = frame;
    published_[static_cast<std::size_t>(interval)] = k + 1;
    if (k > 0) {
      paced_s_ += compute_s;
      ++paced_frames_;
    }
  }
  changed_.notify_all();
}

void FrameStream::finish() {
  {
    const std::lock_guard lock(mutex_);
    finished_ = true;
  }
  changed_.notify_all();
}

bool FrameStream::onset_fits(int made, int total, double mean_frame_s, double period_s) {
  if (made >= total) return true;
  if (made < std::min(total, kLeadFrames) || mean_frame_s <= 0.0) return false;
  const double pace_s = kPaceMargin * mean_frame_s;
  const double due_early_s = 0.5 * period_s;
  // Frame j (from 0 at the onset) is ready (j - made + 1) paces from now and flips j periods after
  // the onset, itself about a period from now: both sides are linear in j, so the first and the
  // last frame still to make decide. (A second interval comes later still than this counts, after
  // the first and what separates them.)
  const auto in_time = [&](int j) { return (j - made + 1) * pace_s <= (j + 1) * period_s - due_early_s; };
  return in_time(made) && in_time(total - 1);
}

int FrameStream::published_total() const { return std::accumulate(published_.begin(), published_.end(), 0); }

bool FrameStream::onset_fits_now(double period_s) const {
  if (finished_) return true;
  if (!begun_) return false;
  const int made = published_total();
  return onset_fits(made, total_, paced_frames_ >= kPacedFrames ? paced_s_ / paced_frames_ : 0.0, period_s);
}

void FrameStream::wait_until_onset_fits(double period_s) {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return onset_fits_now(period_s); });
  ready_ = published_total();
}

bool FrameStream::wait_for(int interval, int k, const GlaredRegion*& frame) {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return begun_ || finished_; });
  frame = nullptr;
  if (!begun_) return false;
  const auto& frames = frames_.at(static_cast<std::size_t>(interval));
  if (frames.empty()) return true;
  const int wanted = std::min(k, static_cast<int>(frames.size()) - 1);
  const int& published = published_[static_cast<std::size_t>(interval)];
  changed_.wait(lock, [&] { return published > wanted || finished_; });
  if (published <= wanted) return false;
  frame = frames[static_cast<std::size_t>(wanted)];
  return true;
}

int FrameStream::ready() const {
  const std::lock_guard lock(mutex_);
  return ready_;
}

int FrameStream::total() const {
  const std::lock_guard lock(mutex_);
  return total_;
}

bool FrameStream::complete() const {
  const std::lock_guard lock(mutex_);
  return begun_ && published_total() >= total_;
}

bool FrameStream::finished() const {
  const std::lock_guard lock(mutex_);
  return finished_;
}

}  // namespace glarelab

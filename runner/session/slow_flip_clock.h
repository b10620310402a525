#pragma once
// A timing self-test: wraps a session clock and makes every Nth flip arrive `extra_periods`
// refresh periods late, as a renderer that misses its deadline would. Selected only through
// RunOptions::slow_flip_every (never by an experiment file), to check that late frames are
// detected, logged with their trial and counted in the session summary.
#include <memory>
#include <string>

#include "core/clock.h"

namespace glarelab {

class SlowFlipClock final : public SessionClock {
 public:
  SlowFlipClock(std::unique_ptr<SessionClock> inner, double refresh_hz, int every_nth_flip, double extra_periods = 1.0)
      : inner_(std::move(inner)), delay_s_(extra_periods / refresh_hz), every_(every_nth_flip) {}
  double now_s() const override { return inner_->now_s() + offset_s_; }
  double on_flip() override { return delayed(inner_->on_flip()); }
  double on_flip_at(std::chrono::steady_clock::time_point presented) override {
    return delayed(inner_->on_flip_at(presented));
  }
  std::string name() const override { return inner_->name() + "+slow-flips"; }
  bool keeps_real_time() const override { return inner_->keeps_real_time(); }

 private:
  double delayed(double flip_s) {
    ++flips_;
    if (every_ > 0 && flips_ % every_ == 0) offset_s_ += delay_s_;
    return flip_s + offset_s_;
  }

  std::unique_ptr<SessionClock> inner_;
  double delay_s_;
  int every_;
  long long flips_ = 0;
  double offset_s_ = 0.0;
};

}  // namespace glarelab

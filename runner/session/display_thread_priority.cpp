#include "runner/session/display_thread_priority.h"

#include <sched.h>

#include <cerrno>
#include <cstring>
#include <utility>

namespace glarelab {
namespace {

constexpr int kRealTimePriority = 1;

bool set_policy(int policy, int priority) {
  sched_param parameters{};
  parameters.sched_priority = priority;
  return sched_setscheduler(0, policy, &parameters) == 0;
}

}  // namespace

DisplayThreadPriority DisplayThreadPriority::raise_before_display() {
  DisplayThreadPriority priority;
  priority.asked_ = true;
  if (set_policy(SCHED_RR, kRealTimePriority)) {
    priority.real_time_ = true;
    priority.description_ =
        "real-time (SCHED_RR, priority 1): the display's thread and the GL driver's threads it started";
  } else {
    const int error = errno;
    priority.description_ = std::string("normal: real-time scheduling was refused (sched_setscheduler: ") +
                            std::strerror(error) +
                            "); it needs CAP_SYS_NICE or an RLIMIT_RTPRIO of 1 or more "
                            "(e.g. \"@lab - rtprio 10\" in /etc/security/limits.d/)";
  }
  return priority;
}

void DisplayThreadPriority::display_opened() {
  if (real_time_) set_policy(SCHED_RR | SCHED_RESET_ON_FORK, kRealTimePriority);
}

DisplayThreadPriority::DisplayThreadPriority(DisplayThreadPriority&& other) noexcept
    : asked_(other.asked_), real_time_(std::exchange(other.real_time_, false)), description_(std::move(other.description_)) {}

DisplayThreadPriority& DisplayThreadPriority::operator=(DisplayThreadPriority&& other) noexcept {
  if (this == &other) return *this;
  if (real_time_ && !other.real_time_) set_policy(SCHED_OTHER, 0);
  asked_ = other.asked_;
  real_time_ = std::exchange(other.real_time_, false);
  description_ = std::move(other.description_);
  return *this;
}

DisplayThreadPriority::~DisplayThreadPriority() {
  // Lowering one's own policy is always permitted.
  if (real_time_) set_policy(SCHED_OTHER, 0);
}

}  // namespace glarelab

#pragma once
// The display's thread at real-time priority for a session on a real clock, where the system
// permits it: what Psychtoolbox's Priority() and PsychoPy's core.rush() ask for. A flip's drawing
// then never waits behind the worker preparing the next trial, nor behind another program.
//
// With a software renderer the drawing is the GL driver's own threads (llvmpipe's rasterisers),
// started with the GL context by the thread that makes it: they inherit its policy only if it is
// raised before the display opens. Once the display is open, threads started later (the trial
// worker, the commit's connection, the helper pools) start at normal priority again
// (SCHED_RESET_ON_FORK): only the display's own work runs above normal.
//
// Linux grants SCHED_RR to a process with CAP_SYS_NICE or an RLIMIT_RTPRIO of 1 or more (for a lab
// group, a line such as "@lab - rtprio 10" in /etc/security/limits.d/); elsewhere the session runs
// at normal priority and its log says why. Priority 1, the lowest real-time priority: above every
// normal thread, below the kernel's and any audio server's real-time threads. The kernel's
// real-time throttling (sched_rt_runtime_us, 95 % of each second by default) keeps a thread that
// never sleeps from taking a core whole.
#include <string>

namespace glarelab {

class DisplayThreadPriority {
 public:
  // Normal priority, nothing changed (a session on the virtual clock).
  DisplayThreadPriority() = default;
  // On the display's thread, before the display opens: SCHED_RR at priority 1 where permitted.
  static DisplayThreadPriority raise_before_display();
  // After the display opened: threads this thread starts from now on begin at normal priority.
  void display_opened();
  // The display's thread back at normal priority (the GL driver's threads keep theirs until the
  // context closes).
  ~DisplayThreadPriority();
  DisplayThreadPriority(DisplayThreadPriority&& other) noexcept;
  // Taking over a raise made on this same thread.
  DisplayThreadPriority& operator=(DisplayThreadPriority&& other) noexcept;
  DisplayThreadPriority(const DisplayThreadPriority&) = delete;
  DisplayThreadPriority& operator=(const DisplayThreadPriority&) = delete;

  bool real_time() const { return real_time_; }
  // Whether a raise was asked for (a session on a real clock).
  bool asked() const { return asked_; }
  // For the session's log: the priority obtained, or why it was not.
  const std::string& description() const { return description_; }

 private:
  bool asked_ = false;
  bool real_time_ = false;
  std::string description_ = "normal (a session on the virtual clock)";
};

}  // namespace glarelab

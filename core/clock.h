#pragma once
// Session clocks. Every time in a session is "seconds since session start" on one of these.
//  - MonotonicClock: steady_clock, for real displays; flips are stamped when the swap returns.
//  - VirtualClock: advances exactly one refresh period per presented frame, so offscreen
//    sessions are deterministic and run as fast as the machine renders.
#include <chrono>
#include <cstdint>
#include <string>

namespace glarelab {

// The process' CPU time over all its threads (CLOCK_PROCESS_CPUTIME_ID), seconds: what a benchmark
// on a shared machine measures beside the wall clock, which other processes inflate.
double process_cpu_time_s();

// One call of `work` timed both ways: its wall clock (steady_clock) and the process' CPU time.
struct CallTimes {
  double wall_s = 0.0, cpu_s = 0.0;
};
template <typename Work>
CallTimes time_call(Work&& work) {
  const double cpu_start = process_cpu_time_s();
  const auto start = std::chrono::steady_clock::now();
  work();
  return {std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), process_cpu_time_s() - cpu_start};
}

class SessionClock {
 public:
  virtual ~SessionClock() = default;
  // Seconds since session start on this clock.
  virtual double now_s() const = 0;
  // Called by the presenter right after a frame was presented; returns that flip's time (s).
  virtual double on_flip() = 0;
  // Called instead of on_flip() by a presenter that knows when, on steady_clock, its frame went
  // out: an offscreen display paced to a refresh grid flips at the boundary it waited for, however
  // late the host woke the process after it (runner/tracker/real_time_pacer.h). Returns that
  // flip's time (s). A clock whose flips are not steady_clock times takes its own flip time.
  virtual double on_flip_at(std::chrono::steady_clock::time_point presented) {
    static_cast<void>(presented);
    return on_flip();
  }
  // "monotonic" or "virtual": written to the log so every time can be traced to its clock.
  virtual std::string name() const = 0;
  // Whether flips wait for the wall clock (a display's refresh): then a frame not ready by its flip
  // is late. A virtual clock's flips wait for nothing but the frame.
  virtual bool keeps_real_time() const = 0;
};

class MonotonicClock final : public SessionClock {
 public:
  // start_offset_s lets a resumed session continue its time line after the last logged flip.
  explicit MonotonicClock(double start_offset_s = 0.0);
  double now_s() const override;
  double on_flip() override { return now_s(); }
  double on_flip_at(std::chrono::steady_clock::time_point presented) override;
  std::string name() const override { return "monotonic"; }
  bool keeps_real_time() const override { return true; }

 private:
  std::chrono::steady_clock::time_point start_;
  double start_offset_s_;
};

class VirtualClock final : public SessionClock {
 public:
  VirtualClock(double refresh_hz, double start_s = 0.0, std::int64_t start_frame = 0);
  // Time of the next flip that has not happened yet.
  double now_s() const override;
  double on_flip() override;
  std::string name() const override { return "virtual"; }
  bool keeps_real_time() const override { return false; }
  std::int64_t frames_presented() const { return frames_; }

 private:
  double period_s_;
  double start_s_;
  std::int64_t frames_;
};

// Seconds of steady_clock since `start`: how long the program's own work took (benchmarks, the
// preparation of frames), never a session's time line.
inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace glarelab

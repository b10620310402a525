#pragma once
// Progress of a run on stdout. On a terminal one status line (trial k of n, block, elapsed, time
// left, what the run is doing now, e.g. preparing glare) is redrawn in place every second by a
// ticker thread, so it moves even while one step takes long; the progress lines of the session are
// printed above it. Elsewhere (a pipe, a file) plain lines at the moments the status changes, at
// most one every 2 s, so a log shows the run advancing without a line per frame.
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <ostream>
#include <streambuf>
#include <string>
#include <thread>

namespace glarelab {

class StatusLine {
 public:
  // `out` is written under the status line's lock only (stream() for everything else printed
  // meanwhile). `terminal`: redraw in place; else plain lines. Its own control sequences (the
  // erase of the line) reach `out` as they are; every text it prints, the session's lines and the
  // status (block names come from experiment files), is escaped (core/text_limits.h), so `out`
  // may be the terminal unfiltered (runner/cli/terminal_stream.h, unescaped_stdout).
  StatusLine(std::ostream& out, bool terminal);
  ~StatusLine();  // the ticker stopped and the status line cleared
  StatusLine(const StatusLine&) = delete;
  StatusLine& operator=(const StatusLine&) = delete;

  // True when stdout is a terminal (isatty).
  static bool stdout_is_terminal();

  // A stream whose lines are printed above the status line (whole lines: a line is written when
  // its newline arrives).
  std::ostream& stream() { return stream_; }

  // What the run is doing when no trial runs (loading scenes, preparing the display): shown on a
  // terminal only.
  void set_step(const std::string& step);
  // Trial `number` (from 1) of `total` starts, in `block` (empty without blocks); the time left is
  // the mean duration of the trials since the first times those still to come.
  void set_trial(int number, int total, const std::string& block);
  // A long part of the current trial ("preparing glare frames"), or empty when it is over.
  void set_detail(const std::string& detail);

  // The status as drawn now ("trial 3 of 34, block 1 of 2: 12 s elapsed, about 40 s left").
  std::string text() const;

 private:
  class LineBuffer : public std::streambuf {
   public:
    explicit LineBuffer(StatusLine& owner) : owner_(owner) {}

   protected:
    int_type overflow(int_type ch) override;
    std::streamsize xsputn(const char* text, std::streamsize count) override;

   private:
    StatusLine& owner_;
    std::string pending_;
  };

  void print_line(const std::string& line);
  void changed_locked();
  void draw_locked();
  std::string text_locked() const;
  void tick();

  std::ostream& out_;
  const bool terminal_;
  LineBuffer buffer_;
  std::ostream stream_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start_ = Clock::now();
  Clock::time_point first_trial_{};
  std::optional<Clock::time_point> last_plain_;
  std::string step_ = "starting";
  int trial_ = 0, total_ = 0;
  std::string block_, detail_;
  std::thread ticker_;
};

}  // namespace glarelab

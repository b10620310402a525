#pragma once
// The boundary where text reaches the terminal: std::cout and std::cerr pass through a filter that
// escapes control characters (core/text_limits.h, escaped_for_terminal) while keeping line breaks
// and tabs. Experiment files, condition tables and databases are written by others: an ESC
// sequence in a condition name must print as "\x1b]0;title\x07", not retitle, clear or recolour
// the terminal, whichever command prints it (validate's summary, analyze's notes, any error).
#include <iosfwd>
#include <memory>

namespace glarelab::cli {

// Installs the filter on std::cout and std::cerr for its lifetime (main's), then restores them,
// flushing what is left.
class TerminalTextGuard {
 public:
  TerminalTextGuard();
  ~TerminalTextGuard();
  TerminalTextGuard(const TerminalTextGuard&) = delete;
  TerminalTextGuard& operator=(const TerminalTextGuard&) = delete;

 private:
  struct Installed;
  std::unique_ptr<Installed> installed_;
};

// Standard output beneath the filter, for a writer that escapes its text itself and must send
// control sequences of its own (the run's status line, runner/session/status_line.h); std::cout
// when no guard is installed. Flush std::cout before switching to it, so that lines stay in order.
std::ostream& unescaped_stdout();

}  // namespace glarelab::cli

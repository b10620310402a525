#include "runner/calibration/terminal_lines.h"

#include <poll.h>
#include <unistd.h>

namespace glarelab {

std::optional<std::string> TerminalLines::poll() {
  while (!closed_) {
    const std::size_t end = pending_.find('\n');
    if (end != std::string::npos) break;
    pollfd input{STDIN_FILENO, POLLIN, 0};
    if (::poll(&input, 1, 0) <= 0 || (input.revents & (POLLIN | POLLHUP)) == 0) break;
    char buffer[256];
    const ssize_t got = ::read(STDIN_FILENO, buffer, sizeof buffer);
    if (got <= 0) {
      closed_ = true;
      break;
    }
    pending_.append(buffer, static_cast<std::size_t>(got));
  }
  std::size_t end = pending_.find('\n');
  if (end == std::string::npos) {
    if (!closed_ || pending_.empty()) return std::nullopt;
    end = pending_.size();  // the last line, typed without a line end before the input closed
  }
  std::string line = pending_.substr(0, end);
  pending_.erase(0, end == pending_.size() ? end : end + 1);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return line;
}

}  // namespace glarelab

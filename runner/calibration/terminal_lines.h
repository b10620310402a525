#pragma once
// Lines typed at the terminal (standard input), read without blocking, so the window keeps
// presenting and reading its keys while the person types a photometer reading.
#include <optional>
#include <string>

namespace glarelab {

class TerminalLines {
 public:
  // The next complete line (without its line end) if one has been typed; never waits.
  std::optional<std::string> poll();
  // Standard input was closed (end of file): no more lines will come.
  bool closed() const { return closed_; }

 private:
  std::string pending_;
  bool closed_ = false;
};

}  // namespace glarelab

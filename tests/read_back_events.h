#pragma once
// The `read_backs` events of a session on the GPU engine, one per glared or perceived interval
// (runner/session/session_glare.cpp): "trial K (MODES, N frame(s) computed for S stimulus
// frame(s)): frame 0 read back ...; after frame 0: F frame ...". What the read-back tests count.
#include <regex>
#include <string>
#include <vector>

#include "session_events.h"

namespace glarelab::test {

struct IntervalReadBacks {
  int frames_computed = -1;               // -1: the message did not read as the pattern above
  unsigned long frames_after_first = 0;  // whole frames read back after frame 0
  std::string message;
};

inline std::vector<IntervalReadBacks> read_back_events(const std::string& db_path) {
  static const std::regex pattern(R"(, (\d+) frame\(s\) computed for .*after frame 0: (\d+) frame)");
  std::vector<IntervalReadBacks> intervals;
  for (const std::string& message : session_event_messages(db_path, "read_backs")) {
    std::smatch match;
    IntervalReadBacks interval;
    interval.message = message;
    if (std::regex_search(message, match, pattern)) {
      interval.frames_computed = std::stoi(match[1]);
      interval.frames_after_first = std::stoul(match[2]);
    }
    intervals.push_back(interval);
  }
  return intervals;
}

}  // namespace glarelab::test

#pragma once
// A few lines on what a session did, read back from the database (so what is printed is what
// was stored): trials, accuracy, frames, dropped frames, timing.
#include <cstdint>
#include <string>

namespace glarelab {

class ResultStore;

struct SessionSummary {
  std::int64_t session_id = 0;
  std::string experiment;
  std::string participant;
  std::string status;
  std::string display_backend;
  std::string observer;
  std::string renderer;
  int trials = 0;
  int scored_trials = 0;  // trials with a right answer
  int correct = 0;
  std::int64_t frames = 0;
  std::int64_t dropped_frames = 0;
  double session_duration_s = 0.0;  // last flip on the session clock
  std::string clock;

  std::string describe(const std::string& db_path) const;
};

SessionSummary summarise_session(const ResultStore& store, std::int64_t session_id);

}  // namespace glarelab

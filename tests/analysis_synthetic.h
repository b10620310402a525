#pragma once
// Synthetic results databases for the analysis tests, written through ResultStore exactly as a
// session would write them.
#include <string>
#include <vector>

#include "core/random.h"
#include "runner/store/result_store.h"

namespace glarelab::test {

inline SessionRecord synthetic_session(const std::string& participant, std::uint64_t seed = 1) {
  SessionRecord session;
  session.experiment = "synthetic";
  session.participant = participant;
  session.seed = seed;
  session.started_utc = "2026-01-01T00:00:00.000Z";
  session.config = "[experiment]\nname = \"synthetic\"\n";
  session.software_version = "test";
  session.renderer = "none";
  session.display_backend = "offscreen";
  session.clock = "virtual";
  session.observer = "simulated";
  return session;
}

// Three frames per trial at 60 Hz from the onset; the second one dropped when `drop`.
inline std::vector<FrameRecord> synthetic_frames(double onset_s, bool drop = false) {
  std::vector<FrameRecord> frames;
  for (int f = 0; f < 3; ++f) {
    FrameRecord frame;
    frame.frame_index = f;
    frame.scheduled_s = onset_s + f / 60.0;
    frame.flip_s = frame.scheduled_s + (drop && f >= 1 ? 1.0 / 60.0 : 0.0);
    frame.dropped = drop && f == 1;
    frames.push_back(frame);
  }
  return frames;
}

struct TrialSpec {
  std::string procedure;
  std::string condition;  // JSON object text
  std::string response;
  std::optional<int> correct;
  std::optional<double> intensity;
  std::string staircase;
  std::optional<int> reversal;
};

// Commits trials in order (onset 2 s apart, response time 0.4 + 0.01 * index s).
inline void commit_trials(ResultStore& store, std::int64_t session_id, const std::vector<TrialSpec>& specs) {
  for (std::size_t i = 0; i < specs.size(); ++i) {
    TrialRecord trial;
    trial.session_id = session_id;
    trial.trial_index = static_cast<int>(i);
    trial.procedure = specs[i].procedure;
    trial.condition = specs[i].condition;
    trial.response = specs[i].response;
    trial.correct = specs[i].correct;
    trial.intensity = specs[i].intensity;
    trial.staircase = specs[i].staircase;
    trial.reversal = specs[i].reversal;
    trial.onset_s = 1.0 + 2.0 * static_cast<double>(i);
    trial.response_time_s = 0.4 + 0.01 * static_cast<double>(i % 50);
    trial.started_utc = "2026-01-01T00:00:00.000Z";
    store.commit_trial(trial, synthetic_frames(trial.onset_s, i % 7 == 3));
  }
}

// A Ritschel-style preference trial: options "dynamic"/"static" shown left/right, the answer
// names the position of `chosen` ("neither" passes through).
inline TrialSpec preference_trial(const std::string& scene, const std::string& instruction, bool dynamic_left,
                                  const std::string& chosen) {
  const std::string left = dynamic_left ? "dynamic" : "static";
  const std::string right = dynamic_left ? "static" : "dynamic";
  TrialSpec spec;
  spec.procedure = "forced_choice";
  spec.condition = "{\"scene\":\"" + scene + "\",\"instruction\":\"" + instruction + "\",\"left\":\"" + left +
                   "\",\"right\":\"" + right + "\"}";
  spec.response = chosen == "neither" ? "neither" : (chosen == left ? "left" : "right");
  return spec;
}

}  // namespace glarelab::test

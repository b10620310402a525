#include "runner/session/trial_schedule.h"

#include <sstream>

namespace glarelab {

const char* to_string(FlipPhase phase) {
  switch (phase) {
    case FlipPhase::inter_trial: return "inter-trial";
    case FlipPhase::screen: return "screen";
    case FlipPhase::fixation: return "fixation";
    case FlipPhase::interval: return "interval";
    case FlipPhase::inter_stimulus: return "inter-stimulus";
    case FlipPhase::response: return "response";
    case FlipPhase::feedback: return "feedback";
  }
  return "?";
}

TrialSchedule schedule_trial(const PresentationSpec& spec, const TrialPlan& plan, bool sequential) {
  TrialSchedule schedule;
  const bool first = plan.trial_index == 0;
  schedule.inter_trial_frames = first ? 0 : spec.inter_stimulus.frames;
  if (first && !spec.instructions.empty()) schedule.screens.push_back({"instructions", spec.instructions});
  if (spec.break_every_trials > 0 && plan.trial_index > 0 && plan.trial_index % spec.break_every_trials == 0)
    schedule.screens.push_back({"break", spec.break_text});
  if (!plan.screen_text.empty()) schedule.screens.push_back({"block", plan.screen_text});

  for (int k = 0; k < spec.fixation.frames; ++k) schedule.timed.push_back({FlipPhase::fixation, -1, -1, -1});
  schedule.intervals = sequential ? 2 : 1;
  int stimulus_frame = 0;
  for (int interval = 0; interval < schedule.intervals; ++interval) {
    if (interval > 0)
      for (int k = 0; k < spec.inter_stimulus.frames; ++k) schedule.timed.push_back({FlipPhase::inter_stimulus, -1, -1, -1});
    if (interval == schedule.intervals - 1) schedule.first_answer_flip = schedule.timed.size();
    if (interval == 0) schedule.onset_flip = schedule.timed.size();
    for (int k = 0; k < plan.stimulus_frames; ++k) schedule.timed.push_back({FlipPhase::interval, interval, stimulus_frame++, k});
  }
  return schedule;
}

std::string describe_trial_phases(int trial_index, const std::vector<PhaseFlip>& flips) {
  std::ostringstream text;
  text << "trial " << trial_index << ":";
  std::size_t start = 0;
  bool first = true;
  while (start < flips.size()) {
    std::size_t end = start + 1;
    while (end < flips.size() && flips[end].phase == flips[start].phase && flips[end].interval == flips[start].interval)
      ++end;
    text << (first ? " " : ", ") << to_string(flips[start].phase);
    if (flips[start].phase == FlipPhase::interval) text << " " << flips[start].interval + 1;
    text << " " << end - start;
    if (flips[start].phase == FlipPhase::interval)
      text << " (frames " << flips[start].stimulus_frame << "-" << flips[end - 1].stimulus_frame << ")";
    first = false;
    start = end;
  }
  text << " flips";
  return text.str();
}

std::string first_words(const std::string& text, std::size_t max_words) {
  std::istringstream words(text);
  std::string word, line;
  std::size_t count = 0;
  while (words >> word) {
    if (count == max_words) return line + " ...";
    line += (count++ == 0 ? "" : " ") + word;
  }
  return line;
}

}  // namespace glarelab

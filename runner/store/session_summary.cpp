#include "runner/store/session_summary.h"

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "runner/store/result_store.h"

namespace glarelab {

SessionSummary summarise_session(const ResultStore& store, std::int64_t session_id) {
  const auto session = store.load_session(session_id);
  if (!session) throw StoreError("SQLite: " + store.path() + ": no session " + std::to_string(session_id));
  SessionSummary summary;
  summary.session_id = session_id;
  summary.experiment = session->experiment;
  summary.participant = session->participant;
  summary.status = session->status;
  summary.display_backend = session->display_backend;
  summary.observer = session->observer;
  summary.renderer = session->renderer;
  summary.clock = session->clock;
  for (const TrialRecord& trial : store.load_trials(session_id)) {
    ++summary.trials;
    if (trial.correct) {
      ++summary.scored_trials;
      summary.correct += *trial.correct;
    }
    for (const FrameRecord& frame : store.load_frames(trial.id)) {
      if (frame.frame_index >= 0) ++summary.frames;  // stimulus frames; negative: the trial's other flips
      summary.dropped_frames += frame.dropped ? 1 : 0;
    }
  }
  summary.session_duration_s = store.last_flip_s(session_id);
  return summary;
}

std::string SessionSummary::describe(const std::string& db_path) const {
  std::ostringstream text;
  text << "Ran '" << experiment << "': session " << session_id << ", participant " << participant << ", " << status
       << "\n";
  text << "  " << trials << " trials";
  if (scored_trials > 0) {
    char percent[32];
    std::snprintf(percent, sizeof percent, "%.1f%%", 100.0 * correct / scored_trials);
    text << ", " << correct << " of " << scored_trials << " correct (" << percent << ")";
  }
  text << "; " << frames << " frames, " << dropped_frames << " dropped; " << session_duration_s << " s on the "
       << clock << " clock\n";
  text << "  display " << display_backend << " (" << renderer << "), observer " << observer << "\n";
  std::error_code ignored;
  const auto absolute = std::filesystem::absolute(db_path, ignored);
  text << "  database: " << (absolute.empty() ? db_path : absolute.string()) << "\n";
  return text.str();
}

}  // namespace glarelab

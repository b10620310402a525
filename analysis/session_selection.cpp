#include "analysis/session_selection.h"

#include <algorithm>
#include <stdexcept>

namespace glarelab::analysis {
namespace {

template <typename T>
bool contains(const std::vector<T>& items, const T& item) {
  return std::find(items.begin(), items.end(), item) != items.end();
}

std::string listed(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "" : ", ") + item;
  return text;
}

}  // namespace

void select_sessions(LoadedData& data, const SessionSelection& selection) {
  if (selection.empty()) return;
  std::vector<std::string> ids, participants;
  for (const LoadedSession& s : data.sessions) {
    if (!contains(ids, std::to_string(s.record.id))) ids.push_back(std::to_string(s.record.id));
    if (!contains(participants, s.record.participant)) participants.push_back(s.record.participant);
  }
  for (std::int64_t id : selection.session_ids)
    if (!contains(ids, std::to_string(id)))
      throw std::invalid_argument("--session " + std::to_string(id) + ": no loaded session has this id (sessions: " + listed(ids) + ")");
  for (const std::string& participant : selection.participants)
    if (!contains(participants, participant))
      throw std::invalid_argument("--participant '" + participant + "': no loaded session has this participant (participants: " +
                                  listed(participants) + ")");
  const std::size_t loaded = data.sessions.size();
  std::erase_if(data.sessions, [&](const LoadedSession& s) {
    const bool id_kept = selection.session_ids.empty() || contains(selection.session_ids, s.record.id);
    const bool participant_kept = selection.participants.empty() || contains(selection.participants, s.record.participant);
    return !(id_kept && participant_kept);
  });
  std::vector<std::string> what;
  for (std::int64_t id : selection.session_ids) what.push_back("--session " + std::to_string(id));
  for (const std::string& participant : selection.participants) what.push_back("--participant " + participant);
  if (data.sessions.empty())
    throw std::invalid_argument("the selection (" + listed(what) + ") keeps none of the " + std::to_string(loaded) + " sessions loaded");
  std::vector<std::string> kept;
  for (const LoadedSession& s : data.sessions) kept.push_back(s.label);
  data.notes.push_back("selected by " + listed(what) + ": " + std::to_string(data.sessions.size()) + " of " +
                       std::to_string(loaded) + " sessions (" + listed(kept) + ")");
}

}  // namespace glarelab::analysis

#pragma once
// `glarelab analyze --session ID --participant P`: which loaded sessions an analysis includes.
// A session is kept when its id is among the ids given (none given: any id) and its participant
// among the participants given (none given: any). An id or participant that names no loaded
// session is a mistake in the command (a typo would otherwise analyse nothing, or everything).
#include <cstdint>
#include <string>
#include <vector>

#include "analysis/loaded_database.h"

namespace glarelab::analysis {

struct SessionSelection {
  std::vector<std::int64_t> session_ids;  // sessions.id, in any database loaded
  std::vector<std::string> participants;  // sessions.participant
  bool empty() const { return session_ids.empty() && participants.empty(); }
};

// Keeps the selected sessions and adds a note saying which were kept. Throws std::invalid_argument
// naming an id or participant that matches no loaded session (with the ones there are), or a
// selection that keeps no session.
void select_sessions(LoadedData& data, const SessionSelection& selection);

}  // namespace glarelab::analysis

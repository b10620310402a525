#pragma once
// The participant number of a new session: it picks the order of an experiment's blocks
// (protocols/block_design.h). Given with --participant-number, taken from the experiment file
// ([procedure] participant_number), or else 1 + the number of sessions of the experiment already
// in the results database, so consecutive participants walk through the counterbalanced orders.
#include <optional>
#include <string>

namespace glarelab {

struct ParticipantNumber {
  int value = 1;
  std::string source;  // how it was chosen, for the 'participant_number' session event
  // Set when the number is 1 + the sessions counted in the database: the session row must then be
  // written only while that count still holds (ResultStore::begin_session_after).
  std::optional<int> earlier_sessions;
};

// Sessions of `experiment_name` in the database at db_path, read without writing (0 when the
// file does not exist yet). Throws StoreError when an existing file cannot be read.
int count_sessions(const std::string& db_path, const std::string& experiment_name);

ParticipantNumber choose_participant_number(const std::optional<int>& from_option,
                                            const std::optional<int>& from_file, const std::string& db_path,
                                            const std::string& experiment_name);

}  // namespace glarelab

#pragma once
// A results database read into plain structs for analysis. The database is opened read-only,
// so analysing never migrates or alters a file (ResultStore would upgrade it on open).
// Schema versions up to kResultsSchemaVersion load; older ones load with a note; the
// optional `adjustments(trial_id, spot, value_cd_m2)` table is read when it exists.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "core/result_records.h"

namespace glarelab::analysis {

// The condition JSON object as (key, value text) pairs in stored order; non-string JSON values
// are kept as their JSON text.
using ConditionFields = std::vector<std::pair<std::string, std::string>>;

struct AdjustmentRecord {
  int spot = 0;
  double value = 0.0;
};

struct LoadedTrial {
  TrialRecord record;
  ConditionFields condition;
  std::vector<FrameRecord> frames;
  std::vector<AdjustmentRecord> adjustments;  // empty when the table is absent
  // The value of `key` in the condition, or nullptr.
  const std::string* condition_value(const std::string& key) const;
};

struct LoadedSession {
  std::string database;  // path it came from
  SessionRecord record;
  std::vector<LoadedTrial> trials;  // by trial_index
  std::vector<TrackerSampleRecord> tracker_samples;  // by session_time_s
  // A label unique over all loaded databases: "participant (db#session)".
  std::string label;
};

struct LoadedData {
  std::vector<LoadedSession> sessions;
  // Statements about what was loaded (older schema, absent tables, unreadable condition text).
  std::vector<std::string> notes;
};

// Parses one condition column value. Throws std::invalid_argument when it is not a JSON object.
ConditionFields parse_condition_json(const std::string& text);

// Loads every session of every database, in the order given. Throws StoreError naming the file
// for a missing file, a file that is not a glarelab database, or a newer schema version.
LoadedData load_databases(const std::vector<std::string>& paths);

}  // namespace glarelab::analysis

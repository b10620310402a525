#pragma once
// The rows of a glarelab results database as plain structs, and the schema version. runner/store
// writes and migrates databases (runner/store/result_store.h); analysis/ reads them without ever
// writing. Both sides need the row shapes of the contract (docs/DATABASE.md, "Tables") and
// neither may include the other, so they live in the base layer.
#include <cstdint>
#include <optional>
#include <string>

namespace glarelab {

// PRAGMA user_version of a current database. 2 added the adjustments table, 3 the frames'
// gaze_age_s, 4 the trials' procedure 'timing_test', 5 the session_owners table, 6 the trials' procedure
// 'straylight' (docs/DATABASE.md "Schema version"); runner/store/schema_migrations.cpp has one
// migration per version.
inline constexpr int kResultsSchemaVersion = 6;

struct SessionRecord {
  std::int64_t id = 0;
  std::string experiment;
  std::string participant;
  std::uint64_t seed = 0;
  std::string started_utc;   // ISO 8601, "2026-11-21T16:30:00.123Z"
  std::string finished_utc;  // empty while running
  std::string status;        // running | completed | aborted
  std::string config;        // the fully resolved experiment (TOML)
  std::string software_version;
  std::string renderer;      // GL_RENDERER / backend description
  std::string display_backend;  // window | offscreen
  std::string clock;            // monotonic | virtual
  std::string observer;         // keyboard | simulated[:NAME] | script:FILE
};

struct TrialRecord {
  std::int64_t id = 0;
  std::int64_t session_id = 0;
  int trial_index = 0;  // from 0 within a session
  int block = 0;
  std::string procedure;  // forced_choice | staircase | quest | adjustment | rating | timing_test | straylight
  std::string condition;  // JSON object of the condition row
  std::optional<double> intensity;
  std::string response;
  std::optional<int> correct;  // 1, 0 or NULL
  std::optional<double> response_time_s;
  double onset_s = 0.0;  // session clock, flip of the first stimulus frame
  std::string staircase;  // empty -> NULL
  std::optional<int> reversal;
  std::string started_utc;  // wall clock (not reproducible; excluded from determinism checks)
};

struct FrameRecord {
  // Stimulus frames: 0, 1, ... within the trial (on across both intervals of a sequential trial).
  // The trial's other flips (screens, fixation, intervals between, response, feedback): -1, -2, ...
  // in flip order (docs/DATABASE.md).
  int frame_index = 0;
  double scheduled_s = 0.0;
  double flip_s = 0.0;
  bool dropped = false;
  // Live glare with a tracker (runner/session/trial_glare.cpp): the age at this flip of the gaze
  // sample the frame's glare window was placed at (flip_s minus the sample's session time).
  // Empty for every other flip.
  std::optional<double> gaze_age_s;
};

// One setting of a double-adjustment trial (Yoshida 2008): which comparison spot and the
// luminance it was left at.
struct AdjustmentSetting {
  int spot = 0;  // 0: left of the target, 1: right
  double value_cd_m2 = 0.0;
};

struct TrackerSampleRecord {
  int eye = 0;
  double device_time_s = 0.0;
  double session_time_s = 0.0;
  std::optional<double> pupil_diameter_mm;
  std::optional<double> gaze_x;
  std::optional<double> gaze_y;
  double confidence = 0.0;
  bool valid = false;
};

}  // namespace glarelab

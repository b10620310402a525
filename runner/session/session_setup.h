#pragma once
// Setting a session up before its first trial: the experiment (a new one, or a resumed session's
// stored design with its committed trials replayed), scenes, procedure and observer, all checked
// before any database write; then the session clock and the session row, created or reopened.
#include <cstdint>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "protocols/experiment.h"
#include "protocols/observer.h"
#include "protocols/procedure.h"
#include "core/clock.h"
#include "runner/display/display_backend.h"
#include "runner/session/participant_number.h"
#include "runner/session/response_device_session.h"
#include "runner/session/session_runner.h"
#include "runner/store/result_store.h"
#include "runner/store/session_lease.h"
#include "runner/tracker/tracker_session.h"
#include "stimuli/scene_library.h"

namespace glarelab {

// Where a run starts, read before anything is written: a new session's experiment (with --seed and
// its participant number), or a resumed session's stored design and its committed trials.
struct SessionStart {
  Experiment experiment;
  std::string db_path;
  std::unique_ptr<ResultStore> store;  // opened here to resume; a new session's opens with its row
  // This process's hold on the session (after `store`, so released before the store closes): taken
  // here to resume, with the session row for a new session.
  std::unique_ptr<SessionLease> lease;
  std::optional<SessionRecord> resumed;
  std::vector<TrialRecord> done_trials;
  std::optional<ParticipantNumber> participant;  // of a new session
  // [glare] straylight = "measured": the measurement taken (logged as a 'straylight_measured' event).
  std::string straylight_measured;
};

// Everything a session needs that comes from the experiment and options, checked before any
// database write.
struct PreparedSession {
  Experiment experiment;
  std::string resolved_config;
  std::unique_ptr<SceneLibrary> scenes;
  std::unique_ptr<Procedure> procedure;
  std::unique_ptr<Observer> observer;  // null for the keyboard
  std::string observer_description;
};

// The experiment to run and, when resuming, the session's stored design and trials (checked:
// not completed, no gap in its trials). Throws ConfigError/StoreError; writes nothing.
SessionStart load_session_start(const RunOptions& options, std::ostream& progress);

// The options a resumed session runs with: its stored clock (sessions.clock) unless --clock
// names it already; another clock, or a window for a virtual-clock session, is a ConfigError.
// A new session's options are returned as they are.
RunOptions keep_resumed_clock(RunOptions options, const SessionStart& start);
// The experiment's [display] output as the display when `run` was given no --display.
RunOptions display_of_experiment(RunOptions options, const Experiment& experiment);

// Scenes, procedure and observer of the experiment, and the checks that tie them to the options.
PreparedSession prepare_session(Experiment experiment, const RunOptions& options);

// Resume: the committed responses, replayed through the procedure, bring it to the state the
// interrupted run had (adaptive procedures continue from the same intensity).
void replay_done_trials(Procedure& procedure, const SessionStart& start);

DisplayRequest display_request(const Experiment& experiment);

// Whether the session keeps real time: a display that does (a window, a headset), a live tracker,
// a response device or --clock real. Asked before the display opens too (its thread's priority,
// runner/session/display_thread_priority.h), from the kind of display asked for.
bool keeps_real_time(bool display_real_time, const TrackerSession& tracker, const ResponseDeviceSession& device,
                     const RunOptions& options);

// The session clock: real time for a window, a live tracker or a response device, else virtual;
// a resumed session's clock continues after its stored flips.
std::unique_ptr<SessionClock> make_session_clock(const DisplayBackend& display, const TrackerSession& tracker,
                                                 const ResponseDeviceSession& device, const SessionStart& start,
                                                 const RunOptions& options);

// The session row: a resumed one reopened (with a `resumed` event), or a new one with its setup
// events (display, duration roundings, participant number, clipping scenes). Opens the store of a
// new session. Returns the session id, or nothing when the participant number was counted from
// the database and another run has since taken it (nothing is written then).
std::optional<std::int64_t> open_session_row(SessionStart& start, const PreparedSession& prepared, const RunOptions& options,
                              const DisplayBackend& display, const SessionClock& clock, const std::string& renderer,
                              int first_trial, int trials_in_design);

}  // namespace glarelab

#pragma once
// The session loop: for each trial, present its frames on the session clock, collect the
// response, score it and commit the trial (with its frames) before the next one starts.
#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "core/errors.h"  // ExitCode: the exit codes of `glarelab run`
#include "core/frame_engine_request.h"
#include "runner/session/response_device_session.h"
#include "runner/session/stimulus_preview.h"
#include "runner/tracker/tracker_session.h"

namespace glarelab {

class StatusLine;

struct RunOptions {
  std::string experiment_path;
  std::string participant = "anonymous";
  std::string db_path;                  // empty: results/<experiment name>.db
  std::string display = "window";       // window | openxr | offscreen | egl | osmesa
  // False when `run` was given no --display: the experiment's [display] output, if it has one,
  // then replaces `display` (the flag wins over the file).
  bool display_chosen = true;
  std::string observer = "keyboard";    // keyboard | simulated | script:FILE
  // --clock: empty for the display's own (a window's real clock; offscreen: the virtual clock unless
  // a live tracker or response device needs the real one), "real" (an offscreen run paced by the
  // wall clock and stamped on it, so late glare frames show as dropped frames) or "virtual".
  std::string clock;
  // --engine (core/frame_engine_request.h) replaces the file's [display] engine; nothing: the file's.
  std::optional<FrameEngineRequest> engine;
  std::optional<std::uint64_t> seed;    // overrides [experiment] seed
  // Picks the block order (runner/session/participant_number.h); empty: the file's, else 1 + the
  // sessions of the experiment already in the database.
  std::optional<int> participant_number;
  std::optional<std::int64_t> resume_session_id;
  // Stop after this many trials as if the run had been cut off (for demonstrations of resume and
  // for tests); the session stays "running".
  std::optional<int> stop_after_trials;
  // Timing self-test (library callers and tests only, never an experiment file): every Nth flip
  // arrives one refresh period late (runner/session/slow_flip_clock.h), so the dropped-frame
  // detection and the session summary can be checked on any machine.
  std::optional<int> slow_flip_every;
  // --save-frames: each trial's first stimulus frame (after glare, with the overlays; linear cd/m2)
  // written as DIR/trial_NNNN.exr, a record of what the participant saw. The directory is made
  // (and checked writable) before the session row; each write takes place before the frame flips.
  std::string save_frames_dir;
  // glarelab render (runner/session/stimulus_preview.h): the session runs until the first trial of
  // each condition asked for and captures its first stimulus frame (RunResult::previews); the
  // caller gives a database of its own to throw away.
  std::optional<StimulusPreview> preview;
  TrackerOptions tracker;  // --tracker and the pupil options (runner/tracker/)
  ResponseDeviceOptions response_device;  // --response-device, --buttons (docs/DEVICES.md)
  // glarelab run's status line (runner/session/status_line.h); null for previews and tests.
  StatusLine* status = nullptr;
};

struct RunResult {
  std::int64_t session_id = 0;
  std::string status;  // completed | aborted | running (stopped early)
  std::string display;  // the display the session ran on (RunOptions::display, or the file's output)
  std::string db_path;
  int trials_in_design = 0;
  int trials_run_now = 0;
  std::int64_t frames_shown = 0;    // stimulus flips in this run
  std::int64_t frames_dropped = 0;  // of them, more than 1.5 refresh periods after the previous flip
  std::string tracker_summary;  // one line, empty without a tracker
  std::string device_summary;   // one line, empty without a response device
  // RunOptions::preview: the captured frames, in the order the session showed them (a condition the
  // session never showed has none; with one condition asked for, that is an error instead).
  std::vector<PreviewFrame> previews;
  // What the preview changed of the procedure's choice to show its condition (a QUEST+ row its
  // track did not pick; protocols/comparison_luminance.h), in words; empty when nothing.
  std::string preview_note;
  // What loading did to the scenes (negative pixels clamped, scenes scaled or cropped to fit their
  // place), one line each, as the session's `scene_load` events say it.
  std::vector<std::string> scene_notes;
};

// Runs (or resumes) a session. Throws ConfigError/ImageError/DisplayError/StoreError; never
// writes to the database before the experiment, scenes, observer and display are all valid.
RunResult run_session(const RunOptions& options, std::ostream& progress);

}  // namespace glarelab

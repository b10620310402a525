#pragma once
// `glarelab timing-test`: after Psychtoolbox's VBLSyncTest, flips a number of frames of a flicker or
// tearing pattern as fast as the display takes them, measures the flip intervals against the
// nominal period, the missed deadlines, the present call and the loop's own work per frame, and
// writes it all to a results database as a session (docs/TIMING.md): one trial of procedure
// `timing_test` with every flip in `frames`, the display's info dump (`display`), the figures
// (`timing_test`) and the session's `frame_timing` line in `session_events`, so `glarelab analyze`
// shows it beside the experiments' sessions.
#include <cstdint>
#include <ostream>
#include <string>

#include "runner/display/display_backend.h"
#include "runner/timing/flip_statistics.h"
#include "runner/timing/timing_pattern.h"

namespace glarelab {

struct TimingTestOptions {
  std::string display = "window";
  DisplayRequest request;
  long frames = 600;
  TimingPattern pattern = TimingPattern::flicker;
  std::string db_path = "results/timing-test.db";
  std::string participant = "rig";  // the sessions table's participant: who or what was tested
};

struct TimingTestResult {
  std::int64_t session_id = 0;
  std::string status;  // completed | aborted
  FlipTimingFigures figures;
};

// Opens the display (DisplayError: exit 3) and then the database (nothing is written before the
// display has opened), runs the frames (Escape, a closed window or Ctrl-C end it early: the frames
// shown are kept and the session is aborted), and writes the session.
TimingTestResult run_timing_test(const TimingTestOptions& options, std::ostream& out);

}  // namespace glarelab

#include "runner/timing/timing_test_run.h"

#include <chrono>
#include <memory>
#include <optional>
#include <stdexcept>
#include <vector>

#include "core/clock.h"
#include "core/software_version.h"
#include "protocols/json_text.h"
#include "runner/display/display_info.h"
#include "runner/session/frame_timing.h"
#include "runner/session/interrupt.h"
#include "runner/session/refresh_rate_check.h"
#include "runner/store/result_store.h"

namespace glarelab {
namespace {

double seconds_between(std::chrono::steady_clock::time_point from, std::chrono::steady_clock::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

// The session's configuration column: what was asked, as TOML.
std::string timing_test_config(const TimingTestOptions& options) {
  return "[timing_test]\nframes = " + std::to_string(options.frames) + "\npattern = \"" + to_string(options.pattern) +
         "\"\n\n[display]\nbackend = \"" + options.display + "\"\nwidth_px = " +
         std::to_string(options.request.width_px) + "\nheight_px = " + std::to_string(options.request.height_px) +
         "\nrefresh_hz = " + std::to_string(options.request.refresh_hz) +
         "\nmonitor = " + std::to_string(options.request.monitor) +
         "\nfullscreen = " + (options.request.fullscreen ? "true" : "false") + "\n";
}

}  // namespace

TimingTestResult run_timing_test(const TimingTestOptions& options, std::ostream& out) {
  install_interrupt_handlers();
  if (options.frames < 2) throw std::invalid_argument("timing-test: --frames must be at least 2 (one interval)");
  refuse_directory_as_database(options.db_path);
  const std::unique_ptr<DisplayBackend> display = create_display(options.display, options.request);
  std::unique_ptr<SessionClock> clock;
  if (display->real_time())
    clock = std::make_unique<MonotonicClock>();
  else
    clock = std::make_unique<VirtualClock>(display->refresh_hz());
  const std::string info = describe_display_info(*display, *clock);

  ResultStore store(options.db_path);
  SessionRecord session;
  session.experiment = "timing-test";
  session.participant = options.participant;
  session.seed = 0;
  session.started_utc = utc_now_iso8601();
  session.status = "running";
  session.config = timing_test_config(options);
  session.software_version = software_version();
  session.renderer = display->gl_info().describe();
  session.display_backend = display->kind();
  session.clock = clock->name();
  session.observer = "none";
  TimingTestResult result;
  result.session_id = store.begin_session(session);
  store.log_event(result.session_id, 0.0, "display", info);
  out << "timing-test: session " << result.session_id << " -> " << options.db_path << ": " << options.frames << " "
      << to_string(options.pattern) << " frames on " << info << "\n";

  const auto frames = static_cast<std::size_t>(options.frames);
  std::vector<FrameRecord> records;
  std::vector<double> flip_s, draw_s, present_s, overhead_s;
  for (auto* values : {&flip_s, &draw_s, &present_s, &overhead_s}) values->reserve(frames);
  records.reserve(frames);
  FrameTimingMonitor monitor(display->refresh_hz());
  std::optional<std::string> abort_reason;
  long missed = 0;
  for (std::size_t k = 0; k < frames && !abort_reason; ++k) {
    const auto start = std::chrono::steady_clock::now();
    draw_timing_pattern(options.pattern, static_cast<long>(k), display->width_px(), display->height_px(),
                        display->frame_framebuffer());
    const auto drawn = std::chrono::steady_clock::now();
    display->present();
    const auto returned = std::chrono::steady_clock::now();
    // From here to the next frame's drawing: the per-flip work of a session's loop (stamp, the
    // late-flip rule, the frame's record, input, the interrupt flag), measured as its overhead.
    const double flip = clock->on_flip();
    const bool late = monitor.on_flip(flip, 0, static_cast<int>(k));
    missed += late ? 1 : 0;
    FrameRecord record;
    record.frame_index = static_cast<int>(k);
    record.scheduled_s = k == 0 ? flip : flip_s.front() + static_cast<double>(k) * monitor.period_s();
    record.flip_s = flip;
    record.dropped = late;
    records.push_back(record);
    flip_s.push_back(flip);
    for (const InputEvent& event : display->poll_input())
      if (event.name == "escape") abort_reason = "Escape pressed";
    if (display->close_requested()) abort_reason = "window closed";
    if (interrupt_requested()) abort_reason = "interrupted";
    const auto done = std::chrono::steady_clock::now();
    draw_s.push_back(seconds_between(start, drawn));
    present_s.push_back(seconds_between(drawn, returned));
    overhead_s.push_back(seconds_between(returned, done));
  }

  result.figures = flip_timing_figures(flip_s, display->refresh_hz(), missed, draw_s, present_s, overhead_s);
  // Late flips are logged after the loop: a database write inside it would be part of what it measures.
  for (const DroppedFrame& late : monitor.dropped())
    store.log_event(result.session_id, records[static_cast<std::size_t>(late.frame_index)].flip_s, "dropped_frame",
                    "frame " + std::to_string(late.frame_index) + ": " + std::to_string(1000.0 * late.interval_s) +
                        " ms since the previous flip");
  TrialRecord trial;
  trial.session_id = result.session_id;
  trial.trial_index = 0;
  trial.block = 0;
  trial.procedure = "timing_test";
  trial.condition = JsonObjectWriter()
                        .add("name", "timing_test")
                        .add("pattern", to_string(options.pattern))
                        .add("frames", std::to_string(options.frames))
                        .str();
  trial.response = "";
  trial.onset_s = flip_s.empty() ? 0.0 : flip_s.front();
  trial.started_utc = utc_now_iso8601();
  store.commit_trial(trial, records);
  const double end_s = clock->now_s();
  store.log_event(result.session_id, end_s, "timing_test", result.figures.describe());
  store.log_event(result.session_id, end_s, "frame_timing", monitor.summary().describe());
  result.status = abort_reason ? "aborted" : "completed";
  if (abort_reason) store.log_event(result.session_id, end_s, "aborted", *abort_reason);
  store.finish_session(result.session_id, result.status);

  std::string lines = result.figures.describe();
  for (std::size_t at = lines.find("; "); at != std::string::npos; at = lines.find("; ", at)) lines.replace(at, 2, "\n  ");
  out << "  " << lines << "\n";
  // A mean interval off the refresh: the likely cause named (no vsync, a compositor, another rate).
  const std::string flip_warning = flip_interval_warning(display->refresh_hz(), result.figures.interval_mean_s);
  if (!flip_warning.empty()) {
    out << "warning: " << flip_warning << "\n";
    store.log_event(result.session_id, end_s, "flip_interval", flip_warning);
  }
  if (abort_reason) out << "timing-test: stopped after " << records.size() << " frames (" << *abort_reason << ")\n";
  return result;
}

}  // namespace glarelab

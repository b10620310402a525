// Glare in a session: the once-per-session log of the glare backend and the eye's inputs, and each
// trial's stimulus frames after glare, prepared before onset, with their skip and gaze-window events.
#include <algorithm>
#include <chrono>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "runner/session/session_loop.h"
#include "stimuli/position_glare.h"

namespace glarelab {
namespace {

std::string describe_glare_window(const GazeWindow& window, const std::optional<TrackerGaze>& tracked) {
  std::string text = "gaze window " + std::to_string(window.width_px) + "x" + std::to_string(window.height_px) +
                     " px at (" + std::to_string(window.x0_px) + ", " + std::to_string(window.y0_px) + "), centred on ";
  if (tracked)
    return text + "gaze (" + std::to_string(tracked->x) + ", " + std::to_string(tracked->y) + ") from the tracker at " +
           std::to_string(tracked->session_time_s) + " s";
  return text + "the display centre (no gaze)";
}

}  // namespace

// --- glare (stimuli/glare_stage.h) ---
// The trial's stimulus frames after glare, all prepared before onset: glare on the CPU takes
// longer than a refresh period (llvmpipe and FFTW), so a window run could not compute it between
// flips. Frame k is computed for the time it is planned to flip, first_flip + k periods.
// Control: empty (the composed frame is shown untouched). Static: one frame serves all.
// Skip decisions are logged once per trial as 'glare_skipped' events.
// Tracker inputs (when a tracker runs) are those known at preparation, for all the trial's
// frames: the filtered pupil, the detected blinks (blink_source "tracker") and the latest gaze.
std::vector<ImageRGBA> SessionLoop::prepare_glare(const TrialPlan& plan, const std::vector<Placement>& placements,
                                                  int flips_before) {
  // A preview (stimulus_preview.h) computes the glare of its own trial's first frame only; other
  // trials' frames are recorded by the dynamic eye, not computed.
  const bool captured = previewed(plan);
  const bool record_only = preview_ != nullptr && !captured;
  GlareMode mode = glare_mode_for(prepared_.experiment.glare, condition_row(plan));
  // A mode per position (stimuli/position_glare.h): one layer per placement.
  std::vector<GlareMode> position_modes;
  if (plan.position_glare.size() == placements.size())
    for (const std::string& name : plan.position_glare) position_modes.push_back(parse_glare_mode(name));
  if (captured && preview_->glare) {
    mode = *preview_->glare;
    position_modes.clear();
  }
  const bool first_capture = captured && !preview_frame_;
  if (first_capture) {
    preview_frame_.emplace();
    preview_frame_->plan = plan;
    preview_frame_->time_s = preview_->time_s.value_or(clock_.now_s() + (1 + flips_before) * period_s_);
    preview_frame_->glare_label = to_string(mode);
    for (std::size_t p = 0; p < position_modes.size(); ++p)
      preview_frame_->glare_label = (p == 0 ? "" : preview_frame_->glare_label + ", ") + plan.positions.at(p) + " " +
                                    to_string(position_modes[p]);
  }
  const auto is_control = [](GlareMode m) { return m == GlareMode::control; };
  if (position_modes.empty() ? mode == GlareMode::control
                             : std::all_of(position_modes.begin(), position_modes.end(), is_control))
    return {};
  const auto is_dynamic = [](GlareMode m) { return m == GlareMode::dynamic; };
  const bool dynamic = position_modes.empty() ? mode == GlareMode::dynamic
                                              : std::any_of(position_modes.begin(), position_modes.end(), is_dynamic);
  if (record_only) {
    // The eye sees these frames (its pupil adapts to them) at the times they flip.
    if (dynamic) {
      renderer_.compose(placements, prepared_.experiment.display.background_cd_m2);
      const double field_cd_m2 = mean_luminance(renderer_.read_stimulus());
      const double first_s = clock_.now_s() + (1 + flips_before) * period_s_;
      for (int k = 0; k < plan.stimulus_frames; ++k) glare_.record_dynamic_frame(first_s + k * period_s_, field_cd_m2);
    }
    display_.make_current();
    return {};
  }
  const GlareSpec& spec = prepared_.experiment.glare;
  std::optional<GazePoint> gaze;
  std::optional<TrackerGaze> tracked;
  if (tracker_.active()) {
    const std::optional<double> pupil_mm = tracker_.measured_pupil_mm();
    if (spec.pupil_source == "tracker" && pupil_mm) glare_.record_measured_pupil(clock_.now_s(), *pupil_mm);
    if (spec.blink_source == "tracker") {
      std::vector<DetectedBlink> blinks;
      for (const TrackerBlinkInterval& blink : tracker_.detected_blinks()) blinks.push_back({blink.onset_s, blink.offset_s});
      glare_.set_detected_blinks(blinks);
    }
    // The frames are prepared now and shown from the flip after `flips_before` more: compensation
    // extrapolates to it.
    tracked = spec.gaze_latency_compensation
                  ? tracker_.predicted_gaze(clock_.now_s() + (1 + flips_before) * period_s_)
                  : tracker_.latest_gaze();
    if (tracked) gaze = GazePoint{tracked->x, tracked->y};
  }
  std::vector<GlareLayer> layers;
  std::string modes_label = to_string(mode);
  if (!position_modes.empty()) {
    modes_label.clear();
    for (std::size_t p = 0; p < placements.size(); ++p) {
      renderer_.compose({placements[p]}, 0.0);
      layers.push_back({renderer_.read_stimulus(), position_modes[p]});
      modes_label += (p == 0 ? "" : ", ") + plan.positions.at(p) + " " + to_string(position_modes[p]);
    }
  }
  renderer_.compose(placements, prepared_.experiment.display.background_cd_m2);
  const ImageRGBA composed = renderer_.read_stimulus();
  const double first_flip_s = captured && preview_->time_s ? *preview_->time_s
                                                           : clock_.now_s() + (1 + flips_before) * period_s_;
  const int count = captured ? 1 : dynamic ? plan.stimulus_frames : 1;
  std::vector<ImageRGBA> frames;
  int skipped = 0, gratings_hidden = 0, closed = 0;
  std::string skip_reason;
  double smallest_pupil_mm = 1e9;
  std::optional<GazeWindow> window;
  int applications = 0;
  const auto preparation_start = std::chrono::steady_clock::now();
  for (int k = 0; k < count; ++k) {
    // Preparing a trial's frames can take many seconds on a CPU: Ctrl-C and SIGTERM are honoured
    // within one frame's work, not after the whole trial's.
    check_interrupt();
    if (aborted_) return {};
    const double time_s = first_flip_s + k * period_s_;
    std::vector<GlareFrameReport> reports;
    if (layers.empty()) {
      GlareFrameReport report;
      frames.push_back(glare_.apply(composed, mode, time_s, &report, gaze));
      reports.push_back(report);
    } else {
      frames.push_back(apply_layered_glare(glare_, composed, layers, time_s, gaze, &reports));
    }
    if (first_capture && k == 0) {
      preview_frame_->time_s = time_s;
      preview_frame_->reports = reports;
    }
    for (const GlareFrameReport& report : reports) {
      ++applications;
      if (report.window && !window) window = report.window;
      if (!report.skip_reason.empty()) {
        ++skipped;
        if (skip_reason.empty()) skip_reason = report.skip_reason;
      }
      if (!report.gratings_in_pupil) ++gratings_hidden;
      if (report.eye_closed && report.convolved) ++closed;  // held PSF; otherwise counted as skipped
      smallest_pupil_mm = std::min(smallest_pupil_mm, report.pupil_diameter_mm);
    }
  }
  if (!presentation_mode_logged_) {
    // Which presentation mode glare trials use, and why (measured on the first one).
    presentation_mode_logged_ = true;
    const double per_frame_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - preparation_start).count() / count;
    store_.log_event(session_id_, clock_.now_s(), "presentation_mode",
                     "glare trials: frames prepared before onset (" + std::to_string(1000.0 * per_frame_s) +
                         " ms per glare frame on this machine against a refresh period of " +
                         std::to_string(1000.0 * period_s_) +
                         " ms; dynamic glare is a function of time and seed, so prepared frames equal live "
                         "ones); control trials: composed live at every refresh");
  }
  const std::string trial = "trial " + std::to_string(plan.trial_index) + " (" + modes_label + "): ";
  const std::string of_frames =
      " of " + std::to_string(applications) + (layers.empty() ? " glare frame(s)" : " glare layer frame(s)");
  if (skipped > 0)
    store_.log_event(session_id_, clock_.now_s(), "glare_skipped",
                     trial + "convolution skipped on " + std::to_string(skipped) + of_frames + ": " + skip_reason);
  if (closed > 0)
    store_.log_event(session_id_, clock_.now_s(), "glare_skipped",
                     trial + "eye closed by a blink on " + std::to_string(closed) + of_frames +
                         ": the PSF of the last open frame is held");
  if (gratings_hidden > 0)
    store_.log_event(session_id_, clock_.now_s(), "glare_skipped",
                     trial + "lens fibre gratings left out on " + std::to_string(gratings_hidden) + of_frames +
                         ": pupil (smallest " + std::to_string(smallest_pupil_mm) +
                         " mm) inside the clear lens centre (cortex annulus from " +
                         std::to_string(2.0 * EyeParameters{}.lens_cortex_inner_radius_mm) + " mm diameter)");
  if (window)
    store_.log_event(session_id_, clock_.now_s(), "glare_window",
                     trial + describe_glare_window(*window, tracked));
  display_.make_current();  // a GL glare backend works in a context of its own
  return frames;
}

void SessionLoop::log_glare_setup() {
  const GlareSpec& spec = prepared_.experiment.glare;
  bool any_glare = false;
  for (const ConditionRow& row : prepared_.experiment.conditions) {
    const auto sides = position_glare_modes(row);
    any_glare = any_glare || glare_mode_for(spec, row) != GlareMode::control ||
                (sides && *sides != std::pair{GlareMode::control, GlareMode::control});
  }
  if (!any_glare) {
    store_.log_event(session_id_, clock_.now_s(), "glare_backend", "none: every condition is control");
    return;
  }
  store_.log_event(session_id_, clock_.now_s(), "glare_backend", glare_.backend_reason());
  display_.make_current();  // making a GL backend (or asking GL for auto) changed the current context
  const bool tracked = tracker_.active();
  std::string inputs = std::string("pupil: ") +
                       (tracked && spec.pupil_source == "tracker" ? "the tracker's filtered pupil (model's until its first sample)"
                                                                  : "the eye model's (Eq. 1-2)") +
                       "; blinks: " +
                       (tracked && spec.blink_source == "tracker" ? "detected by the tracker" : "the eye model's schedule");
  if (!tracked && (spec.blink_source == "tracker" || spec.pupil_source == "tracker"))
    inputs += " (no tracker: the model's)";
  if (spec.gaze_window_px > 0)
    inputs += "; gaze window " + std::to_string(spec.gaze_window_px) + " px around " +
              (tracked ? std::string(spec.gaze_latency_compensation
                                         ? "the tracker's gaze extrapolated to each trial's first flip"
                                         : "the tracker's latest gaze (no latency compensation)")
                       : "the display centre: no tracker, no gaze");
  store_.log_event(session_id_, clock_.now_s(), "glare_inputs", inputs);
}

const ConditionRow& SessionLoop::condition_row(const TrialPlan& plan) const {
  for (const ConditionRow& row : prepared_.experiment.conditions)
    if (row.name() == plan.condition_name) return row;
  throw std::logic_error("session: trial " + std::to_string(plan.trial_index) + " names condition '" +
                         plan.condition_name + "', which the experiment does not have");
}
// --- end glare ---

}  // namespace glarelab

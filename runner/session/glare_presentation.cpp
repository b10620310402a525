// How glare trials are presented (prepared before onset or live, [glare] presentation, settled
// from the measured cost), and the session's once-only glare records: the backend and the eye's
// inputs, the observer's optics per condition, and the perception stages' settings and cost.
#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/number_text.h"
#include "glare/wave/luidolt_kernel.h"
#include "runner/session/session_glare.h"
#include "stimuli/position_glare.h"

namespace glarelab {
namespace {

// The median of a per-frame cost series, its first frame left out when there are others: the
// first frame of a session also makes the FFTW plans and buffers.
double steady_median_s(const std::vector<double>& series) {
  if (series.empty()) return 0.0;
  std::vector<double> steady(series.begin() + (series.size() > 1 ? 1 : 0), series.end());
  std::sort(steady.begin(), steady.end());
  return steady[steady.size() / 2];
}

// Why presenting glare frames prepared before onset costs the participant nothing but the gaze.
constexpr const char* kPreparedEqualsLive =
    "prepared frames equal live ones: dynamic glare is a function of time and seed; only the gaze is the one known at "
    "the trial's start";

// Seconds in milliseconds, to the microsecond.
std::string ms_text(double seconds) { return number_text(std::round(seconds * 1e6) / 1e3); }

// The glare modes of an interval's positions, sorted, whatever their sides: "control + dynamic",
// "dynamic + static", or one mode for the whole frame.
std::string glare_modes(const IntervalGlare& glare) {
  if (glare.layer_modes.empty()) return to_string(glare.mode);
  std::vector<std::string> modes;
  for (const GlareMode mode : glare.layer_modes) modes.push_back(to_string(mode));
  std::sort(modes.begin(), modes.end());
  std::string layout;
  for (const std::string& mode : modes) layout += (layout.empty() ? "" : " + ") + mode;
  return layout;
}

// What settles a presentation together: the glare modes and, for perception intervals, the stages
// (one frame of "glare" alone and one of "glare" through every stage cost different times).
std::string frame_layout(const IntervalGlare& glare) {
  if (!glare.perceived()) return glare_modes(glare);
  return "perception " + perception_stages_label(glare.perception) +
         (glare.glared() ? " with " + glare_modes(glare) + " glare" : std::string(" without glare"));
}

// The trials an interval's presentation speaks of.
std::string trials_named(const IntervalGlare& glare) { return glare.perceived() ? "perception trials" : "glare trials"; }

// "where the glare is dynamic", "where the frame is perception tone_mapping with dynamic glare".
std::string where_layout(const IntervalGlare& glare) {
  return (glare.perceived() ? "where the frame is " : "where the glare is ") + frame_layout(glare);
}

}  // namespace

SessionGlare::GlarePresentation SessionGlare::presentation_for(const IntervalGlare& glare) const {
  const GlarePresentationRequest asked = prepared_.experiment.glare.presentation;
  if (asked == GlarePresentationRequest::live) return GlarePresentation::live;
  if (asked == GlarePresentationRequest::prepared) return GlarePresentation::prepared;
  const auto settled = settled_presentations_.find(frame_layout(glare));
  return settled == settled_presentations_.end() ? GlarePresentation::prepared : settled->second;
}

void SessionGlare::review_live_presentation(const TrialPlan& plan, const IntervalGlare& glare) {
  if (prepared_.experiment.glare.presentation != GlarePresentationRequest::automatic || glare.live_frames_dropped == 0) return;
  const std::string layout = frame_layout(glare);
  const auto settled = settled_presentations_.find(layout);
  if (settled == settled_presentations_.end() || settled->second != GlarePresentation::live) return;
  // The settling measured a median; a real clock's frames vary around it (the machine's other
  // work, the first frames after a pause), and a late live frame is a frame the participant did
  // not see in time. Prepared frames cannot be late for their glare, so the layout goes back to them.
  settled->second = GlarePresentation::prepared;
  std::string cost;
  if (!glare.frame_compute_s.empty()) {
    const double longest_s = *std::max_element(glare.frame_compute_s.begin(), glare.frame_compute_s.end());
    cost = " (its frames took " + ms_text(steady_median_s(glare.frame_compute_s)) + " ms as a median, " +
           ms_text(longest_s) + " ms at most, against a refresh period of " + ms_text(period_s_) + " ms)";
  }
  log_trial_event(clock_.now_s(), "presentation_mode",
                  trials_named(glare) + ": frames prepared before onset from trial " +
                       std::to_string(plan.trial_index + 1) + " " + where_layout(glare) + ": live, trial " +
                       std::to_string(plan.trial_index) + " dropped " + std::to_string(glare.live_frames_dropped) +
                       " of its " + std::to_string(glare.live_frames_shown) + " computed frame(s)" + cost + "; " +
                       kPreparedEqualsLive);
}

bool SessionGlare::presentation_settled(const IntervalGlare& glare) const {
  const GlarePresentationRequest asked = prepared_.experiment.glare.presentation;
  if (asked != GlarePresentationRequest::automatic) return presentation_logged_;
  return settled_presentations_.count(frame_layout(glare)) > 0;
}

// How computed intervals are presented ([glare] presentation): "prepared" and "live" as asked
// (logged once, with the first computed interval's cost); "auto" prepares the first interval of
// each layout (its glare modes, and its perception stages where it has any) before onset,
// measuring what a frame costs (its glare and stages, and drawing it: the region, the overlays,
// the encode), and presents that layout live from then on when the two together fit
// kLiveBudgetFraction of the refresh period (the rest is the flip's margin). Perception frames
// live are computed in the order they flip, as prepared ones are, so the eye's adaptation
// (Luidolt 2020, Eq. 5.2) sees the same sequence either way. Each settled layout is logged as a
// 'presentation_mode' event.
void SessionGlare::settle_glare_presentation(const TrialPlan& plan, const IntervalGlare& glare) {
  if (!glare.computed() || glare.frame_compute_s.empty() || presentation_settled(glare)) return;
  const GlarePresentationRequest asked = prepared_.experiment.glare.presentation;
  // The first frame of a session also makes the FFTW plans and buffers: the steady cost is the
  // median of the frames after it, so "auto" waits for an interval of two frames or more (a dynamic
  // one; a static interval computes one frame).
  const std::size_t measured = glare.frame_compute_s.size();
  if (asked == GlarePresentationRequest::automatic && measured < 2) return;
  const double compute_s = steady_median_s(glare.frame_compute_s);
  // Drawing a glare flip (the region, the overlays, the encode) is the rest of a live frame's
  // cost: on a GPU a fraction of a millisecond, on a software renderer one or more.
  const double draw_s = steady_median_s(glare.frame_draw_s);
  const double per_frame_s = compute_s + draw_s;
  const std::string cost = ms_text(compute_s) + (glare.perceived() ? " ms per perception frame" : " ms per glare frame") +
                           " on this machine" +
                           (glare.frame_draw_s.empty() ? std::string() : " and " + ms_text(draw_s) + " ms to draw it") +
                           " (median of " + std::to_string(measured - (measured > 1 ? 1 : 0)) + " frame(s) of trial " +
                           std::to_string(plan.trial_index) + (measured > 1 ? ", its first frame left out" : "") +
                           ") against a refresh period of " + ms_text(period_s_) + " ms";
  const std::string layout = frame_layout(glare);
  std::string message;
  if (asked == GlarePresentationRequest::live) {
    message = trials_named(glare) + ": live, each frame computed just before its flip ([glare] presentation = \"live\"); " +
              cost + (per_frame_s > period_s_ ? ": longer than a period, so a real-time display drops frames" : "");
  } else if (asked == GlarePresentationRequest::prepared) {
    message = trials_named(glare) + ": frames prepared before onset ([glare] presentation = \"prepared\"); " + cost;
  } else if (per_frame_s <= kLiveBudgetFraction * period_s_) {
    settled_presentations_[layout] = GlarePresentation::live;
    message = trials_named(glare) + ": live from trial " + std::to_string(plan.trial_index + 1) + " " +
              where_layout(glare) + ", each frame computed just before its flip with the gaze of that moment; " + cost +
              (glare.frame_draw_s.empty() ? " fits " : ", together " + ms_text(per_frame_s) + " ms, fit ") +
              number_text(kLiveBudgetFraction * 100.0) + " % of it (trial " + std::to_string(plan.trial_index) +
              " was prepared before onset to measure it)";
  } else {
    settled_presentations_[layout] = GlarePresentation::prepared;
    message = trials_named(glare) + ": frames prepared before onset " + where_layout(glare) + "; " + cost +
              (glare.frame_draw_s.empty() ? " exceeds " : ", together " + ms_text(per_frame_s) + " ms, exceed ") +
              number_text(kLiveBudgetFraction * 100.0) +
              " % of it, so live frames would be dropped (" + kPreparedEqualsLive + ")";
  }
  presentation_logged_ = true;
  store_.log_event(session_id_, clock_.now_s(), "presentation_mode", message + "; control trials: composed live at every refresh");
}

void SessionGlare::log_glare_setup() {
  const GlareSpec& spec = prepared_.experiment.glare;
  bool any_glare = false;
  for (const ConditionRow& row : prepared_.experiment.conditions) {
    const auto sides = position_glare_modes(row);
    any_glare = any_glare || glare_mode_for(spec, row) != GlareMode::control ||
                (sides && *sides != std::pair{GlareMode::control, GlareMode::control});
    frame_sequences_ = frame_sequences_ || glare_mode_for(spec, row) == GlareMode::dynamic ||
                       (sides && (sides->first == GlareMode::dynamic || sides->second == GlareMode::dynamic));
  }
  for (const ConditionRow& row : prepared_.experiment.conditions)
    engines_chosen_ = engines_chosen_ || any_glare || any_perception_stage(perception_for(prepared_.experiment.perception, row));
  // The observer's optics, one event per condition (docs/DATABASE.md): what the trials of that
  // condition (the trials table's condition column names it) were blurred with.
  for (const ConditionRow& row : prepared_.experiment.conditions)
    if (const auto found = condition_refractions_.find(row.name()); found != condition_refractions_.end())
      store_.log_event(session_id_, clock_.now_s(), "observer_refraction",
                       describe_condition_refraction(found->second) +
                           (glare_mode_for(spec, row) == GlareMode::control && !position_glare_modes(row)
                                ? "; a control condition: shown without glare, so not blurred"
                                : ""));
  const FrameEngineRequest asked = prepared_.experiment.engine;
  const std::string engine_asked = "asked for " + std::string(spelling(asked)) + " ([display] engine or --engine)";
  if (!any_glare) {
    store_.log_event(session_id_, clock_.now_s(), "glare_backend", "none: every condition is control");
    bool perceived = false;
    for (const ConditionRow& row : prepared_.experiment.conditions)
      perceived = perceived || any_perception_stage(perception_for(prepared_.experiment.perception, row));
    if (!perceived) {
      store_.log_event(session_id_, clock_.now_s(), "engine",
                       engine_asked + ": none runs, every frame is shown as composed (no glare, no perception stage)");
      return;
    }
    FrameEngine& engine = eyes_.front()->engine;
    store_.log_event(session_id_, clock_.now_s(), "engine",
                     engine_asked + ": " + engine.reason() +
                         (asked == FrameEngineRequest::automatic ? " Why: " + engine.glare().backend_reason()
                                                                 : std::string()) +
                         " Stages: " + engine.stage_backends() + ".");
    display_.make_current();
    return;
  }
  // Every eye's stage picks its backend as the first eye's does.
  GlareStage& stage = eyes_.front()->engine.glare();
  const DisplaySpec& stage_display = eyes_.front()->display;
  std::string backend_reason = stage.backend_reason();
  if (!condition_refractions_.empty()) backend_reason += " " + stage.refraction_backend_reason() + ".";
  backend_reason += " " + eyes_.front()->engine.reason();
  store_.log_event(session_id_, clock_.now_s(), "glare_backend", backend_reason);
  // Each eye's engine is chosen as the first eye's is; "auto" says why its glare backend was taken.
  store_.log_event(session_id_, clock_.now_s(), "engine",
                   engine_asked + ": " + eyes_.front()->engine.reason() +
                       (asked == FrameEngineRequest::automatic ? " Why: " + stage.backend_reason() : std::string()) +
                       " Stages: " + eyes_.front()->engine.stage_backends() + ".");
  display_.make_current();  // making a GL backend (or asking GL for auto) changed the current context
  // The analytic models' kernels are integrated over the display's pixels now, before the first
  // trial (seconds for a full screen), not at the first glare trial's onset.
  std::set<GlareModel> analytic_models;
  bool luidolt = false;
  for (const ConditionRow& row : prepared_.experiment.conditions) {
    const GlareModel model = glare_model_for(spec, row);
    luidolt = luidolt || model == GlareModel::luidolt;
    if (model != GlareModel::ritschel && model != GlareModel::luidolt) analytic_models.insert(model);
  }
  if (luidolt) {
    LuidoltKernelOptions options;
    options.grid_px = spec.grid_px;
    options.wavelength_count = spec.wavelength_samples;
    store_.log_event(session_id_, clock_.now_s(), "glare_model", "luidolt: " + luidolt_description(options));
  }
  for (const GlareModel model : analytic_models) {
    // Each eye's kernel for its view (the first eye's described).
    for (std::size_t e = 1; e < eyes_.size(); ++e)
      eyes_[e]->engine.glare().analytic_for(model, eyes_[e]->display.width_px, eyes_[e]->display.height_px);
    const AnalyticGlare& analytic = stage.analytic_for(model, stage_display.width_px, stage_display.height_px);
    // The human eye's halo kernel too, before the first trial (GlareStage::lenticular_halo_for).
    if (model == GlareModel::human)
      for (const std::unique_ptr<SessionEye>& eye : eyes_)
        eye->engine.glare().lenticular_halo_for(eye->display.width_px, eye->display.height_px);
    store_.log_event(session_id_, clock_.now_s(), "glare_model",
                     to_string(model) + (model == GlareModel::hybrid || model == GlareModel::human ? " (far field " + analytic.describe() + ")"
                                                                    : ": " + analytic.describe()));
  }
  const bool tracked = tracker_.active();
  std::string inputs = std::string("pupil: ") +
                       (tracked && spec.pupil_source == PupilSource::tracker ? "the tracker's filtered pupil (model's until its first sample)"
                                                                  : "the eye model's (Eq. 1-2)") +
                       "; blinks: " +
                       (tracked && spec.blink_source == BlinkSource::tracker ? "detected by the tracker" : "the eye model's schedule");
  if (!tracked && (spec.blink_source == BlinkSource::tracker || spec.pupil_source == PupilSource::tracker))
    inputs += " (no tracker: the model's)";
  if (spec.gaze_window_px > 0)
    inputs += "; gaze window " + std::to_string(spec.gaze_window_px) + " px around " +
              (tracked ? std::string(spec.gaze_latency_compensation
                                         ? "the tracker's gaze extrapolated to each trial's first flip"
                                         : "the tracker's latest gaze (no latency compensation)")
                       : "the display centre: no tracker, no gaze");
  store_.log_event(session_id_, clock_.now_s(), "glare_inputs", inputs);
}

void SessionGlare::log_perception_stages(const TrialPlan& plan, const IntervalGlare& glare) {
  if (!glare.perceived() || glare.frame_compute_s.empty() || perception_logged_) return;
  perception_logged_ = true;
  // As for the glare: the first frame of a session also makes buffers and plans, so the steady
  // cost is the median of the frames after it when there are any.
  const std::size_t measured = glare.frame_compute_s.size();
  const double per_frame_s = steady_median_s(glare.frame_compute_s);
  const PerceptionSettings& s = prepared_.experiment.perception;
  const PerceptionSettings& shown = glare.perception;
  // Where the stages run is the frame engine's (its `engine` event); when each trial's frames were
  // made, ahead on the worker or at the trial, its `trial_preparation` event.
  std::string text = "Fig. 6.1 order on the frame engine's stages (the engine event names them); [perception] " +
                     perception_stages_label(s) + "; trial " + std::to_string(plan.trial_index) + " ran " +
                     perception_stages_label(shown) + (glare.glared() ? " with its glare after adaptation" : "") + ": " +
                     ms_text(per_frame_s) + " ms per frame (median of " +
                     std::to_string(measured - (measured > 1 ? 1 : 0)) + " frame(s)" +
                     (measured > 1 ? ", the first left out" : "") + ") against a refresh period of " +
                     ms_text(period_s_) + " ms" +
                     (per_frame_s < period_s_ ? " (a frame within its period)" : " (longer than a period)");
  text += "; adaptation: gaze sigma " + number_text(s.adaptation_weighting.gaze_sigma_frame_widths) +
          " frame widths (gaze: " + (tracker_.active() ? "the tracker's" : "the display centre") + "), tau_rod " +
          number_text(s.adaptation_time_constants.rod_time_constant_s) + " s, tau_cone " +
          number_text(s.adaptation_time_constants.cone_time_constant_s) + " s" +
          (adapts_ ? "; the adapted luminance is the glare's field luminance" : "");
  text += "; acuity: " + to_string(s.acuity_settings.sigma_form) + ", max sigma " +
          number_text(s.acuity_settings.max_sigma_px) + " px; tone mapping: " + to_string(s.tone_mapping_settings.curve) +
          "; scotopic: " + to_string(s.scotopic_settings.form);
  // The first eye's (in stereo each eye's is in the stereo_eyes event).
  if (!glare.eyes.empty() && !glare.eyes.front().adapted_cd_m2.empty())
    text += "; adapted luminance of its first frame " + number_text(glare.eyes.front().adapted_cd_m2.front()) + " cd/m2";
  store_.log_event(session_id_, clock_.now_s(), "perception_stages", text);
}

}  // namespace glarelab

// Glare in a session: each interval's glare set up (runner/session/interval_glare.h): its modes, its
// composed frame and what each eye sees of it through the condition's optics; its frames prepared
// before onset (computed by runner/session/eye_glare.cpp, live or prepared), and its skip,
// gaze-window and gaze-latency events.
#include <algorithm>
#include <cmath>
#include <chrono>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "runner/session/condition_depth_of_field.h"
#include "runner/session/session_glare.h"
#include "core/number_text.h"
#include "stimuli/frame_depth.h"
#include "stimuli/position_glare.h"

namespace glarelab {
namespace {
// Threads of the spectacle warp of a frame (stimuli/spectacle_warp.h; the result does not depend
// on them): the two cores glarelab is built to run on.
constexpr int kSpectacleThreads = 2;

std::string describe_glare_window(const GazeWindow& window, const std::optional<TrackerGaze>& tracked) {
  std::string text = "gaze window " + std::to_string(window.width_px) + "x" + std::to_string(window.height_px) +
                     " px at (" + std::to_string(window.x0_px) + ", " + std::to_string(window.y0_px) + "), centred on ";
  if (tracked)
    return text + "gaze (" + std::to_string(tracked->x) + ", " + std::to_string(tracked->y) + ") from the tracker at " +
           std::to_string(tracked->session_time_s) + " s";
  return text + "the display centre (no gaze)";
}

// Depth (one float a pixel, row 0 at the top, `frame_width_px` wide) in `view`.
std::vector<float> depth_in_view(const std::vector<float>& frame_depth_m, int frame_width_px, const PixelRect& view) {
  std::vector<float> depth_m;
  depth_m.reserve(static_cast<std::size_t>(view.width_px) * static_cast<std::size_t>(view.height_px));
  for (int y = view.y_px; y < view.y_px + view.height_px; ++y) {
    const auto row = frame_depth_m.begin() + static_cast<std::ptrdiff_t>(y) * frame_width_px + view.x_px;
    depth_m.insert(depth_m.end(), row, row + view.width_px);
  }
  return depth_m;
}

// The interval's glare modes for its events and the preview: one mode for the frame, or one per
// position ("left dynamic, right control"), with the condition's model, gain and spectacles.
std::string modes_label(const TrialPlan& plan, GlareMode mode, const std::vector<GlareMode>& position_modes,
                        GlareModel model, double gain, const ConditionRefraction* refraction) {
  std::string label = to_string(mode);
  if (!position_modes.empty()) {
    label.clear();
    for (std::size_t p = 0; p < position_modes.size(); ++p)
      label += (p == 0 ? "" : ", ") + plan.positions.at(p) + " " + to_string(position_modes[p]);
  }
  if (model != GlareModel::ritschel) label += ", " + to_string(model) + " model";
  if (gain != 1.0) label += ", gain " + number_text(gain);
  if (refraction != nullptr) {
    const SpheroCylinder residual = refraction->fixation.residual.prescription();
    const auto dioptres = [](double value) { return number_text(std::round(value * 1e3) / 1e3 + 0.0); };
    label += ", spectacles " + refraction->spectacles + " (residual " + dioptres(residual.sphere_dioptres) + " / " +
             dioptres(residual.cylinder_dioptres) + " x " + dioptres(residual.axis_deg) + " D)";
  }
  if (!position_modes.empty() && plan.glare_keeps_peak) label += ", glared peak kept";
  return label;
}

}  // namespace

// --- glare (stimuli/glare_stage.h) ---
// An interval's glare: frame k is computed for the time it is planned to flip, first_flip + k
// periods, so a frame is the same whether it is prepared before onset or computed live just before
// its flip (dynamic glare is a function of time and seed). Control: no frames (the composed frame
// is shown untouched). Static: one frame serves all. Tracker inputs (when a tracker runs): the
// filtered pupil and detected blinks known at the interval's start; the gaze known then
// (prepared), or at each frame (live).
IntervalGlare SessionGlare::begin_interval(const TrialPlan& plan, const std::vector<Placement>& placements,
                                           int flips_before) {
  // A trial prepared before the session's first flip (no inter-trial interval or screen before
  // it) would find the tracker unread and take the display centre: the tracker is read up to now,
  // so that the first trial's gaze, pupil and blinks are the latest samples, as every later
  // trial's are (docs/PERCEPTION.md: the gaze known at the interval's first flip).
  if (tracker_.active() && !tracker_.polled()) tracker_.on_frame(clock_.now_s());
  return begin_interval_at(plan, placements, clock_.now_s() + (1 + flips_before) * period_s_, nullptr);
}

IntervalGlare SessionGlare::begin_interval_off_display(const TrialPlan& plan, const std::vector<Placement>& placements,
                                                       double first_flip_s, const CpuComposition& composition) {
  return begin_interval_at(plan, placements, first_flip_s, &composition);
}

ImageRGBA SessionGlare::composed(const std::vector<Placement>& placements, double background_cd_m2,
                                 const CpuComposition* composition) {
  if (composition != nullptr) return composition->compose(placements, background_cd_m2);
  if (exact_composition_ != nullptr && exact_composition_->exact(placements))
    return exact_composition_->compose(placements, background_cd_m2);
  renderer_.compose(placements, background_cd_m2);
  return renderer_.read_stimulus();
}

IntervalGlare SessionGlare::begin_interval_at(const TrialPlan& plan, const std::vector<Placement>& placements,
                                              double first_flip_s, const CpuComposition* composition) {
  // Off the display's thread nothing may touch GL: the display's context stays where it is.
  const auto back_to_display = [&] {
    if (composition == nullptr) display_.make_current();
  };
  IntervalGlare glare;
  glare.eyes.resize(eyes_.size());
  glare.period_s = period_s_;
  glare.first_flip_s = first_flip_s;
  // A preview (stimulus_preview.h) computes the glare of its own trial's first frame only; other
  // trials' frames are recorded by the dynamic eye, not computed.
  const bool captured = capture_.captures(plan);
  const bool record_only = capture_.preview != nullptr && !captured;
  glare.mode = glare_mode_for(prepared_.experiment.glare, condition_row(plan));
  const GlareModel model = glare_model_for(prepared_.experiment.glare, condition_row(plan));
  const double gain = glare_gain_for(condition_row(plan));
  // The observer's residual refraction at the display in this condition (its spectacles). With
  // the depth of field on, the defocus of each depth is that stage's blur, and the PSF keeps only
  // the eye's LCA (runner/session/condition_depth_of_field.h).
  const ConditionOptics optics = condition_optics(plan);
  const std::optional<DioptricPower> residual_error =
      optics.refraction == nullptr ? std::nullopt
      : optics.depth_of_field      ? std::optional(DioptricPower{})
                                   : std::optional(optics.refraction->fixation.residual);
  for (const std::unique_ptr<SessionEye>& eye : eyes_) {
    eye->engine.glare().set_condition(model, gain);
    eye->engine.glare().set_refraction(residual_error);
  }
  // A mode per position (stimuli/position_glare.h): one layer per placement.
  std::vector<GlareMode> position_modes;
  if (plan.position_glare.size() == plan.scenes.size())
    for (const std::string& name : plan.position_glare) position_modes.push_back(parse_glare_mode(name));
  if (captured && capture_.preview->glare) {
    glare.mode = *capture_.preview->glare;
    position_modes.clear();
  }
  if (captured && capture_.preview->time_s) glare.first_flip_s = *capture_.preview->time_s;
  glare.modes_label = modes_label(plan, glare.mode, position_modes, model, gain, optics.refraction);
  glare.perception = perception_for(prepared_.experiment.perception, condition_row(plan));
  const bool perceived = any_perception_stage(glare.perception);
  glare.stimulus_frames = plan.stimulus_frames;
  if (perceived) glare.modes_label += ", perception " + perception_stages_label(glare.perception);
  const bool labels_preview = captured && !capture_.frame;
  if (labels_preview) {
    capture_.frame.emplace();
    capture_.frame->plan = plan;
    capture_.frame->time_s = glare.first_flip_s;
    capture_.frame->glare_label = glare.modes_label;
  }
  const auto is_control = [](GlareMode m) { return m == GlareMode::control; };
  const bool glared = !(position_modes.empty() ? glare.mode == GlareMode::control
                                               : std::all_of(position_modes.begin(), position_modes.end(), is_control));
  if (!glared && !perceived) {
    // Composed live at every refresh; the session's adapting eyes still see it.
    if (adapts_) {
      if (tracker_.active()) update_glare_gaze(glare, glare.first_flip_s);
      const ImageRGBA frame = composed(placements, prepared_.experiment.display.background_cd_m2, composition);
      see_interval(glare, &frame);
      back_to_display();
    }
    return glare;
  }
  const auto is_dynamic = [](GlareMode m) { return m == GlareMode::dynamic; };
  // The analytic models have no moving eye: a dynamic condition's frames are all alike, so one
  // serves the interval (the adaptation luminance of a trial's frames is the same). Luidolt's
  // kernel follows the eye's pupil.
  const bool moving_eye = uses_wave_optics(model) || model == GlareModel::luidolt;
  const bool dynamic = position_modes.empty() ? glare.mode == GlareMode::dynamic
                                              : std::any_of(position_modes.begin(), position_modes.end(), is_dynamic);
  glare.motion = !glared                  ? IntervalGlareMotion::none
                 : moving_eye && dynamic ? IntervalGlareMotion::moving
                                         : IntervalGlareMotion::still;
  if (record_only) {
    // The eyes see these frames (their pupils adapt to them, and the perception stages' eyes) at
    // the times they flip, as computing them would have made it.
    if (glare.motion == IntervalGlareMotion::moving || adapts_) {
      if (tracker_.active()) update_glare_gaze(glare, glare.first_flip_s);
      record_interval(glare, composed(placements, prepared_.experiment.display.background_cd_m2, composition));
    }
    back_to_display();
    return glare;
  }
  glare.made = perceived ? IntervalFrames::perception : IntervalFrames::glare;
  // Adaptation changes every frame (Eq. 5.2), so each is computed; otherwise a static eye's frame
  // serves the whole interval.
  const bool every_frame = glare.motion == IntervalGlareMotion::moving || glare.perception.adaptation;
  // The last capture of a preview ends the session at its first frame; an earlier one's trial runs
  // on, its frames seen by the eyes as in the session.
  glare.frames_needed = captured && capture_.captures_last() ? 1 : every_frame ? plan.stimulus_frames : 1;
  if (tracker_.active()) {
    feed_tracker_inputs();
    update_glare_gaze(glare, glare.first_flip_s);
  }
  see_through_optics(glare, plan, placements, optics, position_modes, composition);
  if (labels_preview) capture_.frame->glare_label = glare.modes_label;  // with the depth of field's part
  // Glare alone: the frames are the eyes' all the same (the perception stages' frames advance
  // them as they are computed).
  if (adapts_ && !perceived) see_interval(glare, nullptr);
  back_to_display();
  return glare;
}

SessionGlare::ConditionOptics SessionGlare::condition_optics(const TrialPlan& plan) const {
  ConditionOptics optics;
  const auto found = condition_refractions_.find(plan.condition_name);
  if (found == condition_refractions_.end()) return optics;
  optics.refraction = &found->second;
  optics.spectacles = found->second.traced_lens != nullptr;
  std::vector<const LoadedScene*> shown;
  for (const std::string& name : plan.scenes) shown.push_back(&prepared_.scenes->get(name));
  optics.depth_of_field = depth_of_field_applies(prepared_.experiment, shown);
  return optics;
}

// Through the condition's spectacles, each eye receives its view of the frame warped by the lens
// (every layer alike), then blurred by the depth of each of its points, accommodated on the depth
// at its own view's centre (each eye a display of its view's size, runner/session/session_eyes.h);
// the glare and the perception stages act on what reaches the eye.
void SessionGlare::see_through_optics(IntervalGlare& glare, const TrialPlan& plan,
                                     const std::vector<Placement>& placements, const ConditionOptics& optics,
                                     const std::vector<GlareMode>& position_modes,
                                     const CpuComposition* composition) {
  const DisplaySpec& display = prepared_.experiment.display;
  std::vector<std::vector<float>> depth_m(eyes_.size());  // each eye's view of the frame's depth
  std::vector<double> depth_field_cd_m2(eyes_.size(), 0.0);
  if (optics.depth_of_field) {
    // Placement r shows the plan's scene r modulo the scenes of a trial (stereo: each eye's view
    // repeats them).
    std::vector<PlacedDepth> placed;
    for (std::size_t r = 0; r < placements.size(); ++r)
      placed.push_back({&prepared_.scenes->get(plan.scenes[r % plan.scenes.size()]).image_cd_m2, placements[r].rect,
                        placements[r].clip});
    const std::vector<float> frame_depth_m = composed_depth_m(
        display.width_px, display.height_px, static_cast<float>(1e-3 * display.viewing_distance_mm), placed);
    // The pupil adapts to the eye's whole view, for every layer alike.
    const ImageRGBA frame = composed(placements, display.background_cd_m2, composition);
    for (std::size_t e = 0; e < eyes_.size(); ++e) {
      const SessionEye& eye = *eyes_[e];
      depth_m[e] = seen_depth_m(*optics.refraction, eye.display,
                                depth_in_view(frame_depth_m, display.width_px, eye.view.viewport), kSpectacleThreads);
      depth_field_cd_m2[e] = mean_luminance(ViewPart(frame, eye.view.viewport).image());
    }
  }
  // The depth of field of each eye's first frame, for the interval's label.
  std::vector<std::optional<std::string>> depth_labels(eyes_.size());
  const auto seen = [&](std::size_t e, const ImageRGBA& frame) {
    const SessionEye& eye = *eyes_[e];
    const ViewPart part(frame, eye.view.viewport);
    ImageRGBA image = optics.spectacles
                          ? frame_through_spectacles(*optics.refraction, eye.display, part.image(), kSpectacleThreads)
                          : part.image();
    if (!optics.depth_of_field) return image;
    FrameDepthOfField blurred = depth_of_field_frame(*optics.refraction, eye.display, image, depth_m[e],
                                                     depth_field_cd_m2[e], kSpectacleThreads);
    if (!depth_labels[e]) depth_labels[e] = describe_frame_depth_of_field(blurred);
    return std::move(blurred.image_cd_m2);
  };
  for (std::size_t p = 0; p < position_modes.size(); ++p) {
    // The position's placement (in stereo, its placement in each eye's view).
    std::vector<Placement> position;
    for (std::size_t q = p; q < placements.size(); q += position_modes.size()) position.push_back(placements[q]);
    const ImageRGBA layer = composed(position, 0.0, composition);
    for (std::size_t e = 0; e < eyes_.size(); ++e)
      glare.eyes[e].layers.push_back({seen(e, layer), position_modes[p], plan.glare_keeps_peak});
  }
  glare.layer_modes = position_modes;
  glare.composed_cd_m2 = composed(placements, display.background_cd_m2, composition);
  for (std::size_t e = 0; e < eyes_.size(); ++e) {
    EyeIntervalGlare& eye = glare.eyes[e];
    const PixelRect& view = eyes_[e]->view.viewport;
    if (!covers_frame(glare.composed_cd_m2, view)) eye.view_cd_m2 = crop_view(glare.composed_cd_m2, view);
    if (optics.spectacles || optics.depth_of_field) eye.through_spectacles = seen(e, glare.composed_cd_m2);
    eye.field_cd_m2 = mean_luminance(eye.seen_cd_m2(glare.composed_cd_m2));
    if (depth_labels[e])
      glare.modes_label += ", " + (eyes_.size() > 1 ? eyes_[e]->view.name + " eye " : std::string()) + *depth_labels[e];
  }
}

void count_glare_reports(IntervalGlare& glare, const std::vector<GlareFrameReport>& reports) {
  for (const GlareFrameReport& report : reports) {
    ++glare.applications;
    if (report.window && !glare.window) glare.window = report.window;
    if (!report.skip_reason.empty()) {
      ++glare.skipped;
      if (glare.skip_reason.empty()) glare.skip_reason = report.skip_reason;
    }
    if (!report.gratings_in_pupil && report.pupil_diameter_mm > 0.0) ++glare.gratings_hidden;  // a wave-optics eye
    if (report.eye_closed && report.convolved) ++glare.closed;  // held PSF; otherwise counted as skipped
    glare.smallest_pupil_mm = std::min(glare.smallest_pupil_mm, report.pupil_diameter_mm);
  }
}

bool SessionGlare::prepare_frames(IntervalGlare& glare, const std::function<bool()>& interrupted, int frames,
                                  bool display_thread) {
  const int last = frames < 0 ? glare.frames_needed : std::min(frames, glare.frames_needed);
  for (int k = 0; k < last; ++k) {
    // Preparing a trial's frames can take many seconds on a CPU: Ctrl-C and SIGTERM are honoured
    // within one frame's work, not after the whole trial's.
    if (interrupted()) return false;
    if (display_thread)
      compute_frame(glare, k);
    else
      make_frame(glare, k);
  }
  return true;
}

void SessionGlare::log_trial_event(double at_s, const std::string& kind, std::string message) {
  if (held_events_ != nullptr)
    held_events_->push_back({at_s, kind, std::move(message)});
  else
    store_.log_event(session_id_, at_s, kind, message);
}

void SessionGlare::log_interval_glare(const TrialPlan& plan, const IntervalGlare& glare) {
  if (!glare.computed()) return;
  const std::string trial = "trial " + std::to_string(plan.trial_index) + " (" + glare.modes_label + "): ";
  const std::string of_frames = " of " + std::to_string(glare.applications) +
                                (glare.layer_modes.empty() ? " glare frame(s)" : " glare layer frame(s)");
  const double now_s = clock_.now_s();
  if (glare.skipped > 0)
    log_trial_event(now_s, "glare_skipped",
                     trial + "convolution skipped on " + std::to_string(glare.skipped) + of_frames + ": " +
                         glare.skip_reason);
  if (glare.closed > 0)
    log_trial_event(now_s, "glare_skipped",
                     trial + "eye closed by a blink on " + std::to_string(glare.closed) + of_frames +
                         ": the PSF of the last open frame is held");
  if (glare.gratings_hidden > 0)
    log_trial_event(now_s, "glare_skipped",
                     trial + "lens fibre gratings left out on " + std::to_string(glare.gratings_hidden) + of_frames +
                         ": pupil (smallest " + std::to_string(glare.smallest_pupil_mm) +
                         " mm) inside the clear lens centre (cortex annulus from " +
                         std::to_string(2.0 * prepared_.experiment.glare.eye.lens_cortex_inner_radius_mm) + " mm diameter)");
  if (glare.window)
    log_trial_event(now_s, "glare_window",
                     trial + describe_glare_window(*glare.window, glare.eyes.front().tracked));
  if (!glare.gaze_to_flip_s.empty()) {
    double sum_s = 0.0, largest_s = 0.0;
    for (const double latency_s : glare.gaze_to_flip_s) {
      sum_s += latency_s;
      largest_s = std::max(largest_s, latency_s);
    }
    const double mean_ms = 1000.0 * sum_s / static_cast<double>(glare.gaze_to_flip_s.size());
    log_trial_event(now_s, "gaze_latency",
                     trial + "gaze to flip mean " + number_text(std::round(mean_ms * 1000.0) / 1000.0) + " ms, max " +
                         number_text(std::round(1000.0 * largest_s * 1000.0) / 1000.0) + " ms over " +
                         std::to_string(glare.gaze_to_flip_s.size()) +
                         (glare.perceived() ? " live perception frame(s)" : " live glare frame(s)"));
  }
}

const ConditionRow& SessionGlare::condition_row(const TrialPlan& plan) const {
  for (const ConditionRow& row : prepared_.experiment.conditions)
    if (row.name() == plan.condition_name) return row;
  throw std::logic_error("session: trial " + std::to_string(plan.trial_index) + " names condition '" +
                         plan.condition_name + "', which the experiment does not have");
}
// --- end glare ---

}  // namespace glarelab

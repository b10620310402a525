// Glare in a session: the once-per-session log of the glare backend and the eye's inputs, and each
// interval's stimulus frames after glare (runner/session/interval_glare.h), prepared before onset
// or computed live before each flip, with their skip, gaze-window and gaze-latency events.
#include <algorithm>
#include <cmath>
#include <chrono>
#include <set>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "runner/session/condition_depth_of_field.h"
#include "runner/session/session_loop.h"
#include "core/number_text.h"
#include "stimuli/frame_depth.h"
#include "stimuli/perception/frame_adaptation_luminance.h"
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

// The box a glared frame can differ from the frame it glared in: the bounding box of every
// report's changed boxes (GlareFrameReport::changed_boxes: the frame is the same bit for bit
// outside them); nothing when a report does not say. No report at all (every layer control): the
// frame is unchanged, and the box is empty.
std::optional<PixelRect> changed_bound(const std::vector<GlareFrameReport>& reports) {
  PixelRect bound;
  for (const GlareFrameReport& report : reports) {
    if (!report.changed_boxes) return std::nullopt;
    bound = bounding_rect(bound, bounding_rect(*report.changed_boxes));
  }
  return bound;
}

}  // namespace

// --- glare (stimuli/glare_stage.h) ---
// An interval's glare: frame k is computed for the time it is planned to flip, first_flip + k
// periods, so a frame is the same whether it is prepared before onset or computed live just before
// its flip (dynamic glare is a function of time and seed). Control: no frames (the composed frame
// is shown untouched). Static: one frame serves all. Tracker inputs (when a tracker runs): the
// filtered pupil and detected blinks known at the interval's start; the gaze known then
// (prepared), or at each frame (live).
IntervalGlare SessionLoop::begin_glare(const TrialPlan& plan, const std::vector<Placement>& placements,
                                       int flips_before) {
  IntervalGlare glare;
  glare.eyes.resize(stereo_eyes_.size());
  glare.period_s = period_s_;
  glare.first_flip_s = clock_.now_s() + (1 + flips_before) * period_s_;
  // A preview (stimulus_preview.h) computes the glare of its own trial's first frame only; other
  // trials' frames are recorded by the dynamic eye, not computed.
  const bool captured = previewed(plan);
  const bool record_only = preview_ != nullptr && !captured;
  glare.mode = glare_mode_for(prepared_.experiment.glare, condition_row(plan));
  const GlareModel model = glare_model_for(prepared_.experiment.glare, condition_row(plan));
  const double gain = glare_gain_for(condition_row(plan));
  glare_.set_condition(model, gain);
  // The observer's residual refraction at the display in this condition (its spectacles). With
  // the depth of field on, the defocus of each depth is that stage's blur, and the PSF keeps only
  // the eye's LCA (runner/session/condition_depth_of_field.h).
  const auto refraction = condition_refractions_.find(plan.condition_name);
  std::vector<const LoadedScene*> shown_scenes;
  for (const std::string& name : plan.scenes) shown_scenes.push_back(&prepared_.scenes->get(name));
  const bool depth_of_field = refraction != condition_refractions_.end() &&
                              depth_of_field_applies(prepared_.experiment, shown_scenes);
  const std::optional<DioptricPower> residual_error =
      refraction == condition_refractions_.end() ? std::nullopt
      : depth_of_field                            ? std::optional(DioptricPower{})
                                                  : std::optional(refraction->second.fixation.residual);
  glare_.set_refraction(residual_error);
  for (const std::unique_ptr<StereoEye>& eye : stereo_eyes_) {
    eye->glare.set_condition(model, gain);
    eye->glare.set_refraction(residual_error);
  }
  // A mode per position (stimuli/position_glare.h): one layer per placement.
  std::vector<GlareMode> position_modes;
  if (plan.position_glare.size() == plan.scenes.size())
    for (const std::string& name : plan.position_glare) position_modes.push_back(parse_glare_mode(name));
  if (captured && preview_->glare) {
    glare.mode = *preview_->glare;
    position_modes.clear();
  }
  if (captured && preview_->time_s) glare.first_flip_s = *preview_->time_s;
  glare.modes_label = to_string(glare.mode);
  if (!position_modes.empty()) {
    glare.modes_label.clear();
    for (std::size_t p = 0; p < position_modes.size(); ++p)
      glare.modes_label += (p == 0 ? "" : ", ") + plan.positions.at(p) + " " + to_string(position_modes[p]);
  }
  if (model != GlareModel::ritschel) glare.modes_label += ", " + to_string(model) + " model";
  if (gain != 1.0) glare.modes_label += ", gain " + number_text(gain);
  if (refraction != condition_refractions_.end()) {
    const SpheroCylinder residual = refraction->second.fixation.residual.prescription();
    const auto dioptres = [](double value) { return number_text(std::round(value * 1e3) / 1e3 + 0.0); };
    glare.modes_label += ", spectacles " + refraction->second.spectacles + " (residual " +
                         dioptres(residual.sphere_dioptres) + " / " + dioptres(residual.cylinder_dioptres) + " x " +
                         dioptres(residual.axis_deg) + " D)";
  }
  if (!position_modes.empty() && plan.glare_keeps_peak) glare.modes_label += ", glared peak kept";
  glare.perception = perception_for(prepared_.experiment.perception, condition_row(plan));
  glare.perceived = any_perception_stage(glare.perception);
  glare.stimulus_frames = plan.stimulus_frames;
  if (glare.perceived) glare.modes_label += ", perception " + perception_stages_label(glare.perception);
  const bool labels_preview = captured && !preview_frame_;
  if (labels_preview) {
    preview_frame_.emplace();
    preview_frame_->plan = plan;
    preview_frame_->time_s = glare.first_flip_s;
    preview_frame_->glare_label = glare.modes_label;
  }
  const auto is_control = [](GlareMode m) { return m == GlareMode::control; };
  glare.glared = !(position_modes.empty() ? glare.mode == GlareMode::control
                                          : std::all_of(position_modes.begin(), position_modes.end(), is_control));
  if (!glare.glared && !glare.perceived) {
    // Composed live at every refresh; the session's adapting eye still sees it.
    if (adapts_) {
      if (tracker_.active()) update_glare_gaze(glare, glare.first_flip_s);
      renderer_.compose(placements, prepared_.experiment.display.background_cd_m2);
      see_interval(glare, renderer_.read_stimulus());
      display_.make_current();
    }
    return glare;
  }
  const auto is_dynamic = [](GlareMode m) { return m == GlareMode::dynamic; };
  // The analytic models have no moving eye: a dynamic condition's frames are all alike, so one
  // serves the interval (the adaptation luminance of a trial's frames is the same).
  const bool moving_eye = model == GlareModel::ritschel || model == GlareModel::hybrid;
  glare.dynamic = glare.glared && moving_eye &&
                  (position_modes.empty() ? glare.mode == GlareMode::dynamic
                                          : std::any_of(position_modes.begin(), position_modes.end(), is_dynamic));
  if (record_only) {
    // The eye sees these frames (its pupil adapts to them, and the perception stages' eye) at the
    // times they flip, as computing them would have made it.
    if (glare.dynamic || adapts_) {
      if (tracker_.active()) update_glare_gaze(glare, glare.first_flip_s);
      renderer_.compose(placements, prepared_.experiment.display.background_cd_m2);
      const ImageRGBA composed = renderer_.read_stimulus();
      const double mean_cd_m2 = mean_luminance(composed);
      const double adaptation_cd_m2 = adapts_ ? adaptation_luminance(glare, composed) : 0.0;
      if (!stereo_eyes_.empty()) record_stereo_interval(glare, composed, plan.stimulus_frames);
      for (int k = 0; stereo_eyes_.empty() && k < plan.stimulus_frames; ++k) {
        if (adapts_) perception_.see(adaptation_cd_m2, glare.first_flip_s, period_s_, k, k + 1);
        const bool adapted = glare.perceived && glare.perception.adaptation;
        if (glare.dynamic)
          glare_.record_dynamic_frame(glare.frame_time_s(k),
                                      adapted ? *perception_.adapted_luminance_cd_m2() : mean_cd_m2);
      }
    }
    display_.make_current();
    return glare;
  }
  glare.active = true;
  // Adaptation changes every frame (Eq. 5.2), so each is computed; otherwise a static eye's frame
  // serves the whole interval.
  const bool every_frame = glare.dynamic || (glare.perceived && glare.perception.adaptation);
  glare.frames_needed = captured ? 1 : every_frame ? plan.stimulus_frames : 1;
  const GlareSpec& spec = prepared_.experiment.glare;
  if (tracker_.active()) {
    const std::optional<double> pupil_mm = tracker_.measured_pupil_mm();
    if (spec.pupil_source == PupilSource::tracker && pupil_mm) glare_.record_measured_pupil(clock_.now_s(), *pupil_mm);
    if (spec.blink_source == BlinkSource::tracker) {
      std::vector<DetectedBlink> blinks;
      for (const TrackerBlinkInterval& blink : tracker_.detected_blinks()) blinks.push_back({blink.onset_s, blink.offset_s});
      glare_.set_detected_blinks(blinks);
    }
    if (!stereo_eyes_.empty()) feed_stereo_tracker_inputs();
    update_glare_gaze(glare, glare.first_flip_s);
  }
  // Through the condition's spectacles, the eye receives the frame warped by the lens (every
  // layer alike), then blurred by the depth of each of its points (the depth of field); the glare
  // and the perception stages act on what reaches the eye.
  const bool spectacles = refraction != condition_refractions_.end() && refraction->second.traced_lens;
  std::vector<float> depth_m;
  double depth_field_cd_m2 = 0.0;
  if (depth_of_field) {
    const DisplaySpec& display = prepared_.experiment.display;
    std::vector<PlacedDepth> placed;
    for (std::size_t i = 0; i < placements.size() && i < shown_scenes.size(); ++i)
      placed.push_back({&shown_scenes[i]->image_cd_m2, placements[i].rect, placements[i].clip});
    depth_m = seen_depth_m(refraction->second, display,
                           composed_depth_m(display.width_px, display.height_px,
                                            static_cast<float>(1e-3 * display.viewing_distance_mm), placed),
                           kSpectacleThreads);
    // The pupil adapts to the whole frame, for every layer alike.
    renderer_.compose(placements, display.background_cd_m2);
    depth_field_cd_m2 = mean_luminance(renderer_.read_stimulus());
  }
  const auto seen = [&](const ImageRGBA& composed) {
    ImageRGBA image = spectacles ? frame_through_spectacles(refraction->second, prepared_.experiment.display, composed,
                                                            kSpectacleThreads)
                                 : composed;
    if (!depth_of_field) return image;
    FrameDepthOfField blurred = depth_of_field_frame(refraction->second, prepared_.experiment.display, image, depth_m,
                                                     depth_field_cd_m2, kSpectacleThreads);
    if (glare.modes_label.find("depth of field") == std::string::npos)
      glare.modes_label += ", " + describe_frame_depth_of_field(blurred);
    return std::move(blurred.image_cd_m2);
  };
  for (std::size_t p = 0; p < position_modes.size(); ++p) {
    // The position's placement (in stereo, its placement in each eye's view).
    std::vector<Placement> position;
    for (std::size_t q = p; q < placements.size(); q += position_modes.size()) position.push_back(placements[q]);
    renderer_.compose(position, 0.0);
    glare.layers.push_back({seen(renderer_.read_stimulus()), position_modes[p], plan.glare_keeps_peak});
  }
  renderer_.compose(placements, prepared_.experiment.display.background_cd_m2);
  glare.composed_cd_m2 = renderer_.read_stimulus();
  if (spectacles || depth_of_field) glare.through_spectacles = seen(glare.composed_cd_m2);
  if (labels_preview) preview_frame_->glare_label = glare.modes_label;  // with the depth of field's part
  glare.field_cd_m2 = mean_luminance(glare.seen_cd_m2());
  // Glare alone: the frames are the eye's all the same (the perception stages' frames advance it
  // as they are computed).
  if (adapts_ && !glare.perceived) see_interval(glare, glare.seen_cd_m2());
  display_.make_current();
  return glare;
}

double SessionLoop::adaptation_luminance(const IntervalGlare& glare, const ImageRGBA& composed_cd_m2) const {
  const GazePoint gaze = glare.gaze.value_or(GazePoint{});
  return frame_adaptation_luminance_cd_m2(composed_cd_m2, gaze.x, gaze.y,
                                          prepared_.experiment.perception.adaptation_weighting);
}

void SessionLoop::see_interval(const IntervalGlare& glare, const ImageRGBA& composed_cd_m2) {
  if (!stereo_eyes_.empty()) return see_stereo_interval(glare, composed_cd_m2);
  perception_.see(adaptation_luminance(glare, composed_cd_m2), glare.first_flip_s, period_s_, 0, glare.stimulus_frames);
}

// The gaze the window is placed at for a frame flipping at `flip_s`: the latest, or with latency
// compensation the gaze extrapolated to that flip.
void SessionLoop::update_glare_gaze(IntervalGlare& glare, double flip_s) {
  glare.tracked = prepared_.experiment.glare.gaze_latency_compensation ? tracker_.predicted_gaze(flip_s)
                                                                       : tracker_.latest_gaze();
  glare.gaze.reset();
  if (glare.tracked) glare.gaze = GazePoint{glare.tracked->x, glare.tracked->y};
  if (!stereo_eyes_.empty()) update_stereo_gaze(glare, flip_s);
}

void SessionLoop::compute_glare_frame(IntervalGlare& glare, int k) {
  if (!glare.active || k >= glare.frames_needed || static_cast<int>(glare.frames.size()) > k) return;
  if (!stereo_eyes_.empty()) return compute_stereo_glare_frame(glare, k);
  const auto start = std::chrono::steady_clock::now();
  const double time_s = glare.frame_time_s(k);
  std::optional<double> gaze_time_s;
  if (presentation_for(glare) == GlarePresentation::live && tracker_.active()) {
    // Live: the gaze of this frame (its age at the flip goes into the frame's row).
    update_glare_gaze(glare, time_s);
    if (glare.tracked) gaze_time_s = glare.tracked->session_time_s;
  }
  glare.gaze_time_s.push_back(gaze_time_s);
  std::vector<GlareFrameReport> reports;
  // The glare of this frame, on the eye adapted to `field` (nothing: the frame's mean luminance).
  const auto glare_of = [&](const ImageRGBA& scene_cd_m2, std::optional<double> field_cd_m2) {
    if (!glare.layers.empty()) {
      // The interval's seen frame: its mean luminance is the one computed once for the interval.
      if (!field_cd_m2 && &scene_cd_m2 == &glare.seen_cd_m2()) field_cd_m2 = glare.field_cd_m2;
      return apply_layered_glare(glare_, scene_cd_m2, glare.layers, time_s, glare.gaze, &reports, field_cd_m2,
                                 &glare.static_layers);
    }
    GlareFrameReport report;
    // The interval's seen frame is the same on every frame: its facts are kept.
    ImageRGBA glared = glare_.apply(scene_cd_m2, glare.mode, time_s, &report, glare.gaze,
                                    field_cd_m2.value_or(glare.field_cd_m2),
                                    &scene_cd_m2 == &glare.seen_cd_m2() ? &glare.seen_facts : nullptr);
    reports.push_back(report);
    return glared;
  };
  // Frame 0 is what --save-frames and glarelab render record, so it is kept exact; the others
  // only reach the display encoder and are kept at half precision, 6 bytes a pixel against 16
  // (runner/session/glared_region.h: the codes shown stay within one of the exact frame's).
  const RegionPrecision kept_at = k == 0 ? RegionPrecision::exact : RegionPrecision::half_rgb;
  if (glare.perceived) {
    // Fig. 6.1: adaptation -> glare -> acuity -> tone mapping -> scotopic colour, the gaze the
    // tracker's when one runs, else the display centre.
    const GazePoint gaze = glare.gaze.value_or(GazePoint{});
    const PerceptionResult result =
        perception_.process(glare.seen_cd_m2(), glare.perception, time_s, period_s_, gaze.x, gaze.y,
                            glare.glared ? FieldGlare(glare_of) : FieldGlare());
    glare.adapted_cd_m2.push_back(result.adapted_luminance_cd_m2);
    glare.frames.push_back(changed_region(glare.composed_cd_m2, result.image, kept_at));
    // One frame serving the interval: the eye still sees the rest of it.
    if (k + 1 == glare.frames_needed)
      perception_.see(result.frame_luminance_cd_m2, glare.first_flip_s, period_s_, glare.frames_needed,
                      glare.stimulus_frames);
  } else {
    const ImageRGBA glared = glare_of(glare.seen_cd_m2(), std::nullopt);
    // Where the glare changed the seen frame; it is the composed frame itself unless seen through
    // spectacles, and then the comparison takes the whole frame.
    const std::optional<PixelRect> differs_within =
        &glare.seen_cd_m2() == &glare.composed_cd_m2 ? changed_bound(reports) : std::nullopt;
    glare.frames.push_back(changed_region(glare.composed_cd_m2, glared, kept_at, differs_within));
  }
  if (k == 0 && preview_frame_ && preview_frame_->reports.empty()) preview_frame_->reports = reports;
  count_glare_reports(glare, reports);
  glare.frame_compute_s.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  display_.make_current();  // a GL glare backend works in a context of its own
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

void SessionLoop::prepare_glare_frames(IntervalGlare& glare) {
  for (int k = 0; k < glare.frames_needed; ++k) {
    // Preparing a trial's frames can take many seconds on a CPU: Ctrl-C and SIGTERM are honoured
    // within one frame's work, not after the whole trial's.
    check_interrupt();
    if (aborted_) return;
    compute_glare_frame(glare, k);
  }
}

void SessionLoop::log_interval_glare(const TrialPlan& plan, const IntervalGlare& glare) {
  if (!glare.active) return;
  const std::string trial = "trial " + std::to_string(plan.trial_index) + " (" + glare.modes_label + "): ";
  const std::string of_frames = " of " + std::to_string(glare.applications) +
                                (glare.layers.empty() ? " glare frame(s)" : " glare layer frame(s)");
  const double now_s = clock_.now_s();
  if (glare.skipped > 0)
    store_.log_event(session_id_, now_s, "glare_skipped",
                     trial + "convolution skipped on " + std::to_string(glare.skipped) + of_frames + ": " +
                         glare.skip_reason);
  if (glare.closed > 0)
    store_.log_event(session_id_, now_s, "glare_skipped",
                     trial + "eye closed by a blink on " + std::to_string(glare.closed) + of_frames +
                         ": the PSF of the last open frame is held");
  if (glare.gratings_hidden > 0)
    store_.log_event(session_id_, now_s, "glare_skipped",
                     trial + "lens fibre gratings left out on " + std::to_string(glare.gratings_hidden) + of_frames +
                         ": pupil (smallest " + std::to_string(glare.smallest_pupil_mm) +
                         " mm) inside the clear lens centre (cortex annulus from " +
                         std::to_string(2.0 * EyeParameters{}.lens_cortex_inner_radius_mm) + " mm diameter)");
  if (glare.window)
    store_.log_event(session_id_, now_s, "glare_window", trial + describe_glare_window(*glare.window, glare.tracked));
  if (!glare.gaze_to_flip_s.empty()) {
    double sum_s = 0.0, largest_s = 0.0;
    for (const double latency_s : glare.gaze_to_flip_s) {
      sum_s += latency_s;
      largest_s = std::max(largest_s, latency_s);
    }
    const double mean_ms = 1000.0 * sum_s / static_cast<double>(glare.gaze_to_flip_s.size());
    store_.log_event(session_id_, now_s, "gaze_latency",
                     trial + "gaze to flip mean " + number_text(std::round(mean_ms * 1000.0) / 1000.0) + " ms, max " +
                         number_text(std::round(1000.0 * largest_s * 1000.0) / 1000.0) + " ms over " +
                         std::to_string(glare.gaze_to_flip_s.size()) + " live glare frame(s)");
  }
}

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
std::string glare_layout(const IntervalGlare& glare) {
  if (glare.layers.empty()) return to_string(glare.mode);
  std::vector<std::string> modes;
  for (const GlareLayer& layer : glare.layers) modes.push_back(to_string(layer.mode));
  std::sort(modes.begin(), modes.end());
  std::string layout;
  for (const std::string& mode : modes) layout += (layout.empty() ? "" : " + ") + mode;
  return layout;
}

}  // namespace

SessionLoop::GlarePresentation SessionLoop::presentation_for(const IntervalGlare& glare) const {
  const GlarePresentationRequest asked = prepared_.experiment.glare.presentation;
  if (asked == GlarePresentationRequest::live) return GlarePresentation::live;
  if (asked == GlarePresentationRequest::prepared) return GlarePresentation::prepared;
  const auto settled = settled_presentations_.find(glare_layout(glare));
  return settled == settled_presentations_.end() ? GlarePresentation::prepared : settled->second;
}

void SessionLoop::review_live_presentation(const TrialPlan& plan, const IntervalGlare& glare) {
  if (prepared_.experiment.glare.presentation != GlarePresentationRequest::automatic || glare.live_frames_dropped == 0) return;
  const std::string layout = glare_layout(glare);
  const auto settled = settled_presentations_.find(layout);
  if (settled == settled_presentations_.end() || settled->second != GlarePresentation::live) return;
  // The settling measured a median; a real clock's frames vary around it (the machine's other
  // work, the first frames after a pause), and a late live frame is a frame the participant did
  // not see in time. Prepared frames cannot be late for their glare, so the layout goes back to them.
  settled->second = GlarePresentation::prepared;
  std::string cost;
  if (!glare.frame_compute_s.empty()) {
    const double longest_s = *std::max_element(glare.frame_compute_s.begin(), glare.frame_compute_s.end());
    cost = " (its glare frames took " + ms_text(steady_median_s(glare.frame_compute_s)) + " ms as a median, " +
           ms_text(longest_s) + " ms at most, against a refresh period of " + ms_text(period_s_) + " ms)";
  }
  store_.log_event(session_id_, clock_.now_s(), "presentation_mode",
                   "glare trials: frames prepared before onset from trial " + std::to_string(plan.trial_index + 1) +
                       " where the glare is " + layout + ": live, trial " + std::to_string(plan.trial_index) + " dropped " +
                       std::to_string(glare.live_frames_dropped) + " of its " + std::to_string(glare.live_frames_shown) +
                       " glare frame(s)" + cost + "; " + kPreparedEqualsLive);
}

bool SessionLoop::presentation_settled(const IntervalGlare& glare) const {
  const GlarePresentationRequest asked = prepared_.experiment.glare.presentation;
  if (asked != GlarePresentationRequest::automatic) return presentation_logged_;
  return settled_presentations_.count(glare_layout(glare)) > 0;
}

// How glare trials are presented ([glare] presentation): "prepared" and "live" as asked (logged
// once, with the first glare interval's cost); "auto" prepares the first glare interval of each
// glare layout before onset, measuring what a frame costs (its glare, and drawing it: the region,
// the overlays, the encode), and presents that layout live from then on when the two together
// fit kLiveBudgetFraction of the refresh period (the rest is the flip's margin). Each settled
// layout is logged as a 'presentation_mode' event.
void SessionLoop::settle_glare_presentation(const TrialPlan& plan, const IntervalGlare& glare) {
  // Perception intervals are always prepared: their cost is the perception_stages event's.
  if (!glare.active || glare.perceived || glare.frame_compute_s.empty() || presentation_settled(glare)) return;
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
  const std::string cost = ms_text(compute_s) + " ms per glare frame on this machine" +
                           (glare.frame_draw_s.empty() ? std::string() : " and " + ms_text(draw_s) + " ms to draw it") +
                           " (median of " + std::to_string(measured - (measured > 1 ? 1 : 0)) + " frame(s) of trial " +
                           std::to_string(plan.trial_index) + (measured > 1 ? ", its first frame left out" : "") +
                           ") against a refresh period of " + ms_text(period_s_) + " ms";
  const std::string layout = glare_layout(glare);
  std::string message;
  if (asked == GlarePresentationRequest::live) {
    message = "glare trials: live, each frame computed just before its flip ([glare] presentation = \"live\"); " +
              cost + (per_frame_s > period_s_ ? ": longer than a period, so a real-time display drops frames" : "");
  } else if (asked == GlarePresentationRequest::prepared) {
    message = "glare trials: frames prepared before onset ([glare] presentation = \"prepared\"); " + cost;
  } else if (per_frame_s <= kLiveBudgetFraction * period_s_) {
    settled_presentations_[layout] = GlarePresentation::live;
    message = "glare trials: live from trial " + std::to_string(plan.trial_index + 1) + " where the glare is " + layout +
              ", each frame computed just before its flip with the gaze of that moment; " + cost +
              (glare.frame_draw_s.empty() ? " fits " : ", together " + ms_text(per_frame_s) + " ms, fit ") +
              number_text(kLiveBudgetFraction * 100.0) + " % of it (trial " + std::to_string(plan.trial_index) +
              " was prepared before onset to measure it)";
  } else {
    settled_presentations_[layout] = GlarePresentation::prepared;
    message = "glare trials: frames prepared before onset where the glare is " + layout + "; " + cost +
              (glare.frame_draw_s.empty() ? " exceeds " : ", together " + ms_text(per_frame_s) + " ms, exceed ") +
              number_text(kLiveBudgetFraction * 100.0) +
              " % of it, so live glare would drop frames (" + kPreparedEqualsLive + ")";
  }
  presentation_logged_ = true;
  store_.log_event(session_id_, clock_.now_s(), "presentation_mode", message + "; control trials: composed live at every refresh");
}

void SessionLoop::log_glare_setup() {
  const GlareSpec& spec = prepared_.experiment.glare;
  bool any_glare = false;
  for (const ConditionRow& row : prepared_.experiment.conditions) {
    const auto sides = position_glare_modes(row);
    any_glare = any_glare || glare_mode_for(spec, row) != GlareMode::control ||
                (sides && *sides != std::pair{GlareMode::control, GlareMode::control});
  }
  // The observer's optics, one event per condition (docs/DATABASE.md): what the trials of that
  // condition (the trials table's condition column names it) were blurred with.
  for (const ConditionRow& row : prepared_.experiment.conditions)
    if (const auto found = condition_refractions_.find(row.name()); found != condition_refractions_.end())
      store_.log_event(session_id_, clock_.now_s(), "observer_refraction",
                       describe_condition_refraction(found->second) +
                           (glare_mode_for(spec, row) == GlareMode::control && !position_glare_modes(row)
                                ? "; a control condition: shown without glare, so not blurred"
                                : ""));
  if (!any_glare) {
    store_.log_event(session_id_, clock_.now_s(), "glare_backend", "none: every condition is control");
    return;
  }
  // In stereo every eye's stage picks its backend as the left eye's does.
  GlareStage& stage = stereo_eyes_.empty() ? glare_ : stereo_eyes_.front()->glare;
  const DisplaySpec& stage_display = stereo_eyes_.empty() ? prepared_.experiment.display : stereo_eyes_.front()->display;
  std::string backend_reason = stage.backend_reason();
  if (!condition_refractions_.empty()) backend_reason += " " + stage.refraction_backend_reason() + ".";
  store_.log_event(session_id_, clock_.now_s(), "glare_backend", backend_reason);
  display_.make_current();  // making a GL backend (or asking GL for auto) changed the current context
  // The analytic models' kernels are integrated over the display's pixels now, before the first
  // trial (seconds for a full screen), not at the first glare trial's onset.
  std::set<GlareModel> analytic_models;
  for (const ConditionRow& row : prepared_.experiment.conditions)
    if (const GlareModel model = glare_model_for(spec, row); model != GlareModel::ritschel) analytic_models.insert(model);
  for (const GlareModel model : analytic_models) {
    // In stereo, each eye's kernel for its view (the left eye's described).
    for (std::size_t e = 1; e < stereo_eyes_.size(); ++e)
      stereo_eyes_[e]->glare.analytic_for(model, stereo_eyes_[e]->display.width_px, stereo_eyes_[e]->display.height_px);
    const AnalyticGlare& analytic = stage.analytic_for(model, stage_display.width_px, stage_display.height_px);
    store_.log_event(session_id_, clock_.now_s(), "glare_model",
                     to_string(model) + (model == GlareModel::hybrid ? " (far field " + analytic.describe() + ")"
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

void SessionLoop::log_perception_stages(const TrialPlan& plan, const IntervalGlare& glare) {
  if (!glare.active || !glare.perceived || glare.frame_compute_s.empty() || perception_logged_) return;
  perception_logged_ = true;
  // As for the glare: the first frame of a session also makes buffers and plans, so the steady
  // cost is the median of the frames after it when there are any.
  const std::size_t measured = glare.frame_compute_s.size();
  const double per_frame_s = steady_median_s(glare.frame_compute_s);
  const PerceptionSettings& s = prepared_.experiment.perception;
  const PerceptionSettings& shown = glare.perception;
  std::string text = "Fig. 6.1 order on the CPU (double precision), frames prepared before onset; [perception] " +
                     perception_stages_label(s) + "; trial " + std::to_string(plan.trial_index) + " ran " +
                     perception_stages_label(shown) + (glare.glared ? " with its glare after adaptation" : "") + ": " +
                     ms_text(per_frame_s) + " ms per frame (median of " +
                     std::to_string(measured - (measured > 1 ? 1 : 0)) + " frame(s)" +
                     (measured > 1 ? ", the first left out" : "") + ") against a refresh period of " +
                     ms_text(period_s_) + " ms";
  text += "; adaptation: gaze sigma " + number_text(s.adaptation_weighting.gaze_sigma_frame_widths) +
          " frame widths (gaze: " + (tracker_.active() ? "the tracker's" : "the display centre") + "), tau_rod " +
          number_text(s.adaptation_time_constants.rod_time_constant_s) + " s, tau_cone " +
          number_text(s.adaptation_time_constants.cone_time_constant_s) + " s" +
          (adapts_ ? "; the adapted luminance is the glare's field luminance" : "");
  text += "; acuity: " + to_string(s.acuity_settings.sigma_form) + ", max sigma " +
          number_text(s.acuity_settings.max_sigma_px) + " px; tone mapping: " + to_string(s.tone_mapping_settings.curve) +
          "; scotopic: " + to_string(s.scotopic_settings.form);
  if (!glare.adapted_cd_m2.empty())
    text += "; adapted luminance of its first frame " + number_text(glare.adapted_cd_m2.front()) + " cd/m2";
  store_.log_event(session_id_, clock_.now_s(), "perception_stages", text);
}

const ConditionRow& SessionLoop::condition_row(const TrialPlan& plan) const {
  for (const ConditionRow& row : prepared_.experiment.conditions)
    if (row.name() == plan.condition_name) return row;
  throw std::logic_error("session: trial " + std::to_string(plan.trial_index) + " names condition '" +
                         plan.condition_name + "', which the experiment does not have");
}
// --- end glare ---

}  // namespace glarelab

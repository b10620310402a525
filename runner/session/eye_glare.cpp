// Each eye's part of a session's glare (runner/session/session_eyes.h; docs/STEREO.md): each eye's
// view of the frame goes through that eye's own glare stage (its own eye model and pupil) and
// perception eye (its own adaptation), with its own gaze, pupil and blinks, and the eyes' parts are
// joined into the frame shown. A mono display has one eye whose view is the whole frame, fed from
// the tracker's binocular reading; a stereo display has two, each fed from its own samples. A
// tracker's gaze is taken as normalised in the eye's own view (a head-mounted tracker reports each
// eye's gaze in that eye's image); without a tracker each eye looks at its view's centre.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "core/number_text.h"
#include "core/gl/read_back.h"
#include "core/pixel_rect.h"
#include "runner/session/session_glare.h"
#include "stimuli/perception/frame_adaptation_luminance.h"
#include "stimuli/position_glare.h"

namespace glarelab {
namespace {

std::string eye_label(const SessionEye& eye) {
  return eye.view.name + " eye (tracker eye " + std::to_string(eye.view.tracker_eye) + ")";
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

std::vector<EyeView> SessionGlare::eye_views() const {
  std::vector<EyeView> views;
  for (const std::unique_ptr<SessionEye>& eye : eyes_) views.push_back(eye->view);
  return views;
}

void SessionGlare::log_stereo_setup() {
  if (prepared_.experiment.display.stereo == StereoMode::none) return;
  const GlareSpec& spec = prepared_.experiment.glare;
  std::string text = "side_by_side:";
  for (const std::unique_ptr<SessionEye>& eye : eyes_)
    text += " " + eye_label(*eye) + " in pixels x " + std::to_string(eye->view.viewport.x_px) + ".." +
            std::to_string(eye->view.viewport.x_px + eye->view.viewport.width_px - 1) + ", eye model seed " +
            std::to_string(eye->seed) + ";";
  text += " each eye its own glare stage and perception eye; pupil: ";
  const bool tracked = tracker_.active();
  text += tracked && spec.pupil_source == PupilSource::tracker ? "each eye's own filtered pupil from the tracker"
                                                    : "each eye model's own (Eq. 1-2)";
  text += "; blinks: ";
  text += tracked && spec.blink_source == BlinkSource::tracker ? "each eye's own, detected by the tracker"
                                                    : "each eye model's own schedule";
  text += "; gaze: ";
  text += tracked ? "each eye's own samples, normalised in its view" : "each view's centre (no tracker)";
  text += " (per-eye samples in tracker_samples by eye id)";
  store_.log_event(session_id_, clock_.now_s(), "stereo", text);
}

std::vector<Placement> SessionGlare::eye_overlays(const std::vector<Placement>& overlays) const {
  std::vector<Placement> repeated;
  const DisplaySpec& display = prepared_.experiment.display;
  for (const std::unique_ptr<SessionEye>& eye : eyes_) {
    const PixelRect& view = eye->view.viewport;
    for (const Placement& overlay : overlays) {
      Placement moved = overlay;
      moved.rect = moved_into_view(overlay.rect, display, eye->view);
      const PixelRect clip = moved_into_view(overlay.clip, display, eye->view);
      // The clip, kept inside the eye's view.
      moved.clip = intersection(clip, view);
      if (moved.clip.empty()) continue;
      repeated.push_back(moved);
    }
  }
  return repeated;
}

void SessionGlare::feed_tracker_inputs() {
  const GlareSpec& spec = prepared_.experiment.glare;
  for (const std::unique_ptr<SessionEye>& eye : eyes_) {
    const int id = eye->view.tracker_eye;
    const bool own = eye->own_tracker_samples;
    if (spec.pupil_source == PupilSource::tracker)
      if (const std::optional<double> pupil_mm = own ? tracker_.measured_eye_pupil_mm(id) : tracker_.measured_pupil_mm())
        eye->engine.glare().record_measured_pupil(clock_.now_s(), *pupil_mm);
    if (spec.blink_source == BlinkSource::tracker) {
      std::vector<DetectedBlink> blinks;
      for (const TrackerBlinkInterval& blink : own ? tracker_.detected_eye_blinks(id) : tracker_.detected_blinks())
        blinks.push_back({blink.onset_s, blink.offset_s});
      eye->engine.glare().set_detected_blinks(blinks);
    }
  }
}

void SessionGlare::update_glare_gaze(IntervalGlare& glare, double flip_s) {
  const bool predicted = prepared_.experiment.glare.gaze_latency_compensation;
  for (std::size_t e = 0; e < eyes_.size(); ++e) {
    const int id = eyes_[e]->view.tracker_eye;
    EyeIntervalGlare& eye = glare.eyes[e];
    if (eyes_[e]->own_tracker_samples)
      eye.tracked = predicted ? tracker_.predicted_eye_gaze(id, flip_s) : tracker_.latest_eye_gaze(id);
    else
      eye.tracked = predicted ? tracker_.predicted_gaze(flip_s) : tracker_.latest_gaze();
    eye.gaze.reset();
    if (eye.tracked) eye.gaze = GazePoint{eye.tracked->x, eye.tracked->y};
  }
}

double SessionGlare::adaptation_luminance(std::size_t e, const IntervalGlare& glare,
                                         const ImageRGBA& eye_part_cd_m2) const {
  const GazePoint gaze = glare.eyes[e].gaze.value_or(GazePoint{});
  return frame_adaptation_luminance_cd_m2(eye_part_cd_m2, gaze.x, gaze.y,
                                          prepared_.experiment.perception.adaptation_weighting);
}

void SessionGlare::see_interval(const IntervalGlare& glare, const ImageRGBA* composed_cd_m2) {
  for (std::size_t e = 0; e < eyes_.size(); ++e) {
    SessionEye& eye = *eyes_[e];
    const auto see = [&](const ImageRGBA& seen_cd_m2) {
      eye.engine.perception().see(adaptation_luminance(e, glare, seen_cd_m2), glare.first_flip_s, period_s_, 0,
                         glare.stimulus_frames);
    };
    if (composed_cd_m2 == nullptr) {
      see(glare.eyes[e].seen_cd_m2(glare.composed_cd_m2));
    } else {
      const ViewPart part(*composed_cd_m2, eye.view.viewport);
      see(part.image());
    }
  }
}

void SessionGlare::record_interval(const IntervalGlare& glare, const ImageRGBA& composed_cd_m2) {
  for (std::size_t e = 0; e < eyes_.size(); ++e) {
    SessionEye& eye = *eyes_[e];
    const ViewPart part(composed_cd_m2, eye.view.viewport);
    const double mean_cd_m2 = mean_luminance(part.image());
    const double adaptation_cd_m2 = adapts_ ? adaptation_luminance(e, glare, part.image()) : 0.0;
    const bool adapted = glare.perception.adaptation;
    for (int k = 0; k < glare.stimulus_frames; ++k) {
      if (adapts_) eye.engine.perception().see(adaptation_cd_m2, glare.first_flip_s, period_s_, k, k + 1);
      if (glare.motion == IntervalGlareMotion::moving)
        eye.engine.glare().record_dynamic_frame(glare.frame_time_s(k),
                                       adapted ? *eye.engine.perception().adapted_luminance_cd_m2() : mean_cd_m2);
    }
  }
}

// Eye e's part of frame k: what it sees of the interval's frame through its perception stages
// (Fig. 6.1: adaptation -> glare -> acuity -> tone mapping -> scotopic colour, at its gaze or its
// view's centre) or through its glare alone.
EyeFrame SessionGlare::eye_frame(std::size_t e, IntervalGlare& glare, int k, std::vector<GlareFrameReport>& reports) {
  SessionEye& eye = *eyes_[e];
  EyeIntervalGlare& part = glare.eyes[e];
  EyeFrameRequest request{part.seen_cd_m2(glare.composed_cd_m2)};
  request.mode = glare.mode;
  request.layers = &part.layers;
  request.static_layers = &part.static_layers;
  request.glared = glare.glared();
  request.perception = glare.perceived() ? &glare.perception : nullptr;
  request.time_s = glare.frame_time_s(k);
  request.frame_time_s = period_s_;
  request.gaze = part.gaze;
  request.field_cd_m2 = part.field_cd_m2;
  request.facts = &part.seen_facts;
  // The engine shares the display's context (SessionGlare's constructor): the GL engine's frame
  // stays on the GPU until the display draws it.
  request.on_gpu = true;
  EyeFrame frame = eye.engine.frame(request);
  reports.insert(reports.end(), frame.reports.begin(), frame.reports.end());
  if (!glare.perceived()) return frame;
  part.adapted_cd_m2.push_back(*frame.adapted_luminance_cd_m2);
  // One frame serving the interval: the eye still sees the rest of it.
  if (k + 1 == glare.frames_needed)
    eye.engine.perception().see(*frame.frame_luminance_cd_m2, glare.first_flip_s, period_s_, glare.frames_needed,
                                glare.stimulus_frames);
  return frame;
}

void SessionGlare::compute_frame(IntervalGlare& glare, int k) {
  if (make_frame(glare, k)) display_.make_current();  // a GL glare backend works in a context of its own
}

bool SessionGlare::make_frame(IntervalGlare& glare, int k) {
  if (!glare.computed() || k >= glare.frames_needed || static_cast<int>(glare.frames.size()) > k) return false;
  const auto start = std::chrono::steady_clock::now();
  const gl::ReadBackTally read_backs_before = gl::read_back_tally();
  std::optional<double> gaze_time_s;
  // The tracker first: a frame prepared ahead on a worker (never with a tracker) must not read the
  // presentations the display's thread settles meanwhile.
  if (tracker_.active() && presentation_for(glare) == GlarePresentation::live) {
    // Live: the gaze of this frame (its age at the flip, its oldest eye's, goes into the frame's row).
    update_glare_gaze(glare, glare.frame_time_s(k));
    for (const EyeIntervalGlare& eye : glare.eyes)
      if (eye.tracked && (!gaze_time_s || eye.tracked->session_time_s < *gaze_time_s))
        gaze_time_s = eye.tracked->session_time_s;
  }
  glare.gaze_time_s.push_back(gaze_time_s);
  std::vector<GlareFrameReport> reports;
  std::optional<ImageRGBA> shown;  // the eyes' parts joined (an eye seeing the whole frame: its part)
  // Where the frame can differ from the composed one: inside each eye's changed boxes where the eye
  // sees its part as it is and its glare says where it changed it; else anywhere.
  std::optional<PixelRect> differs_within = PixelRect{};
  // The eyes' parts that stayed on the GPU (the GL engine), and those made on the host.
  std::vector<GlaredRegion::GpuPart> gpu_parts;
  std::vector<std::pair<ImageRGBA, PixelRect>> host_parts;
  for (std::size_t e = 0; e < eyes_.size(); ++e) {
    std::vector<GlareFrameReport> eye_reports;
    EyeFrame part = eye_frame(e, glare, k, eye_reports);
    glare.add_gpu_stage_times(part.gpu_stages_s);
    const PixelRect& view = eyes_[e]->view.viewport;
    const std::optional<PixelRect> bound = changed_bound(eye_reports);
    if (glare.perceived() || glare.eyes[e].through_spectacles || !bound)
      differs_within.reset();
    else if (differs_within)
      differs_within = bounding_rect(*differs_within, PixelRect{bound->x_px + view.x_px, bound->y_px + view.y_px,
                                                                bound->width_px, bound->height_px});
    if (part.gpu_image_cd_m2) {
      gpu_parts.push_back({std::move(part.gpu_image_cd_m2), view});
    } else {
      host_parts.emplace_back(std::move(part.image_cd_m2), view);
    }
    for (const GlareFrameReport& report : eye_reports)
      if (report.pupil_diameter_mm > 0.0) {
        glare.eyes[e].pupil_sum_mm += report.pupil_diameter_mm;
        ++glare.eyes[e].pupil_frames;
      }
    reports.insert(reports.end(), eye_reports.begin(), eye_reports.end());
  }
  if (!gpu_parts.empty()) {
    // On the GPU, where it is drawn from: an eye answered on the host beside it is uploaded.
    for (const auto& [image, view] : host_parts)
      gpu_parts.push_back({std::make_shared<gl::GlFrameBuffer>(image), view});
    glare.frames.push_back(gpu_region(std::move(gpu_parts)));
  } else {
    for (auto& [image, view] : host_parts) {
      if (covers_frame(glare.composed_cd_m2, view)) {
        shown = std::move(image);
      } else {
        if (!shown) shown = glare.composed_cd_m2;
        paste_view(*shown, image, view);
      }
    }
    // Frame 0 is what --save-frames and glarelab render record, so it is kept exact; the others
    // only reach the display encoder and are kept at half precision, 6 bytes a pixel against 16
    // (runner/session/glared_region.h: the codes shown stay within one of the exact frame's).
    const RegionPrecision kept_at = k == 0 ? RegionPrecision::exact : RegionPrecision::half_rgb;
    glare.frames.push_back(changed_region(glare.composed_cd_m2, *shown, kept_at, differs_within));
    // What changed since the frame before: all a flip that follows that frame's must draw.
    if (glare.frames.size() >= 2) mark_changes_since(glare.frames.back(), glare.frames[glare.frames.size() - 2]);
  }
  if (k == 0 && capture_.frame && capture_.frame->reports.empty()) capture_.frame->reports = reports;
  count_glare_reports(glare, reports);
  glare.frame_compute_s.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  // What frame 0 read back, and the tally the interval's later read-backs are counted from
  // (report_interval's `read_backs` event).
  if (k == 0) {
    glare.read_backs_first_frame = gl::read_back_tally().since(read_backs_before);
    glare.read_backs_after_first_from = gl::read_back_tally();
  }
  return true;
}

bool SessionGlare::computes_off_display_thread() {
  // The GL engine's stages run in GL contexts made on the display's thread.
  if (!engines_chosen_) return true;  // no frame is computed at all
  for (const std::unique_ptr<SessionEye>& eye : eyes_)
    if (eye->engine.kind() != FrameEngineKind::cpu) return false;
  display_.make_current();  // choosing the engine may have made a context of its own current
  return true;
}

void SessionGlare::log_stereo_eyes(const TrialPlan& plan, const IntervalGlare& glare) {
  if (prepared_.experiment.display.stereo == StereoMode::none || !glare.computed()) return;
  std::string text = "trial " + std::to_string(plan.trial_index) + " (" + glare.modes_label + "):";
  for (std::size_t e = 0; e < eyes_.size() && e < glare.eyes.size(); ++e) {
    const EyeIntervalGlare& eye = glare.eyes[e];
    text += (e == 0 ? " " : "; ") + eye_label(*eyes_[e]) + ": pupil ";
    text += eye.pupil_frames > 0 ? "mean " + number_text(std::round(eye.pupil_sum_mm / eye.pupil_frames * 1e4) / 1e4) +
                                       " mm over " + std::to_string(eye.pupil_frames) + " frame(s)"
                                 : std::string("none (no wave-optics glare)");
    if (eye.tracked)
      text += ", gaze (" + number_text(eye.tracked->x) + ", " + number_text(eye.tracked->y) + ") from the tracker at " +
              number_text(eye.tracked->session_time_s) + " s";
    else
      text += ", gaze at its view's centre";
    if (!eye.adapted_cd_m2.empty()) text += ", adapted luminance of its first frame " + number_text(eye.adapted_cd_m2.front()) + " cd/m2";
  }
  log_trial_event(clock_.now_s(), "stereo_eyes", text);
}

}  // namespace glarelab

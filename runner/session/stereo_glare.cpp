// A stereo session's per-eye work ([display] stereo = "side_by_side"; docs/STEREO.md): each eye's
// half of the composed frame goes through that eye's own glare stage (its own eye model and
// pupil) and perception eye (its own adaptation), with its own gaze, pupil and blinks from a
// binocular tracker, and the halves are joined into the frame shown. A tracker's gaze is taken as
// normalised in the eye's own view (a head-mounted tracker reports each eye's gaze in that eye's
// image); without a tracker each eye looks at its view's centre.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "core/number_text.h"
#include "runner/session/session_loop.h"
#include "stimuli/perception/frame_adaptation_luminance.h"
#include "stimuli/position_glare.h"

namespace glarelab {
namespace {

std::string eye_label(const StereoEye& eye) {
  return eye.view.name + " eye (tracker eye " + std::to_string(eye.view.tracker_eye) + ")";
}

}  // namespace

std::vector<EyeView> SessionLoop::stereo_views() const {
  std::vector<EyeView> views;
  for (const std::unique_ptr<StereoEye>& eye : stereo_eyes_) views.push_back(eye->view);
  return views;
}

void SessionLoop::log_stereo_setup() {
  if (stereo_eyes_.empty()) return;
  const GlareSpec& spec = prepared_.experiment.glare;
  std::string text = "side_by_side:";
  for (const std::unique_ptr<StereoEye>& eye : stereo_eyes_)
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

std::vector<Placement> SessionLoop::stereo_overlays(const std::vector<Placement>& overlays) const {
  std::vector<Placement> repeated;
  const DisplaySpec& display = prepared_.experiment.display;
  for (const std::unique_ptr<StereoEye>& eye : stereo_eyes_) {
    const PixelRect& view = eye->view.viewport;
    for (const Placement& overlay : overlays) {
      Placement moved = overlay;
      moved.rect = moved_into_view(overlay.rect, display, eye->view);
      const PixelRect clip = moved_into_view(overlay.clip, display, eye->view);
      // The clip, kept inside the eye's view.
      const int x0 = std::max(clip.x_px, view.x_px), y0 = std::max(clip.y_px, view.y_px);
      const int x1 = std::min(clip.x_px + clip.width_px, view.x_px + view.width_px);
      const int y1 = std::min(clip.y_px + clip.height_px, view.y_px + view.height_px);
      if (x1 <= x0 || y1 <= y0) continue;
      moved.clip = {x0, y0, x1 - x0, y1 - y0};
      repeated.push_back(moved);
    }
  }
  return repeated;
}

void SessionLoop::feed_stereo_tracker_inputs() {
  const GlareSpec& spec = prepared_.experiment.glare;
  for (const std::unique_ptr<StereoEye>& eye : stereo_eyes_) {
    const int id = eye->view.tracker_eye;
    if (spec.pupil_source == PupilSource::tracker)
      if (const std::optional<double> pupil_mm = tracker_.measured_eye_pupil_mm(id))
        eye->glare.record_measured_pupil(clock_.now_s(), *pupil_mm);
    if (spec.blink_source == BlinkSource::tracker) {
      std::vector<DetectedBlink> blinks;
      for (const TrackerBlinkInterval& blink : tracker_.detected_eye_blinks(id)) blinks.push_back({blink.onset_s, blink.offset_s});
      eye->glare.set_detected_blinks(blinks);
    }
  }
}

void SessionLoop::update_stereo_gaze(IntervalGlare& glare, double flip_s) {
  glare.eyes.resize(stereo_eyes_.size());
  for (std::size_t e = 0; e < stereo_eyes_.size(); ++e) {
    const int id = stereo_eyes_[e]->view.tracker_eye;
    EyeIntervalGlare& eye = glare.eyes[e];
    eye.tracked = prepared_.experiment.glare.gaze_latency_compensation ? tracker_.predicted_eye_gaze(id, flip_s)
                                                                       : tracker_.latest_eye_gaze(id);
    eye.gaze.reset();
    if (eye.tracked) eye.gaze = GazePoint{eye.tracked->x, eye.tracked->y};
  }
}

double SessionLoop::eye_adaptation_luminance(const StereoEye& eye, const IntervalGlare& glare, std::size_t e,
                                             const ImageRGBA& composed_cd_m2) const {
  const GazePoint gaze = e < glare.eyes.size() ? glare.eyes[e].gaze.value_or(GazePoint{}) : GazePoint{};
  return frame_adaptation_luminance_cd_m2(crop_view(composed_cd_m2, eye.view.viewport), gaze.x, gaze.y,
                                          prepared_.experiment.perception.adaptation_weighting);
}

void SessionLoop::see_stereo_interval(const IntervalGlare& glare, const ImageRGBA& composed_cd_m2) {
  for (std::size_t e = 0; e < stereo_eyes_.size(); ++e) {
    StereoEye& eye = *stereo_eyes_[e];
    eye.perception.see(eye_adaptation_luminance(eye, glare, e, composed_cd_m2), glare.first_flip_s, period_s_, 0,
                       glare.stimulus_frames);
  }
}

void SessionLoop::record_stereo_interval(IntervalGlare& glare, const ImageRGBA& composed_cd_m2, int frames) {
  for (std::size_t e = 0; e < stereo_eyes_.size(); ++e) {
    StereoEye& eye = *stereo_eyes_[e];
    const double mean_cd_m2 = mean_luminance(crop_view(composed_cd_m2, eye.view.viewport));
    const double adaptation_cd_m2 = adapts_ ? eye_adaptation_luminance(eye, glare, e, composed_cd_m2) : 0.0;
    const bool adapted = glare.perceived && glare.perception.adaptation;
    for (int k = 0; k < frames; ++k) {
      if (adapts_) eye.perception.see(adaptation_cd_m2, glare.first_flip_s, period_s_, k, k + 1);
      if (glare.dynamic)
        eye.glare.record_dynamic_frame(glare.frame_time_s(k),
                                       adapted ? *eye.perception.adapted_luminance_cd_m2() : mean_cd_m2);
    }
  }
}

// Frame k of a stereo interval: what compute_glare_frame does for a mono frame, once per eye on
// its half, the halves joined into one frame.
void SessionLoop::compute_stereo_glare_frame(IntervalGlare& glare, int k) {
  const auto start = std::chrono::steady_clock::now();
  const double time_s = glare.frame_time_s(k);
  std::optional<double> gaze_time_s;
  if (presentation_for(glare) == GlarePresentation::live && tracker_.active()) {
    update_glare_gaze(glare, time_s);
    // The frame's gaze age is its older eye's.
    for (const EyeIntervalGlare& eye : glare.eyes)
      if (eye.tracked && (!gaze_time_s || eye.tracked->session_time_s < *gaze_time_s))
        gaze_time_s = eye.tracked->session_time_s;
  }
  glare.gaze_time_s.push_back(gaze_time_s);
  glare.eyes.resize(stereo_eyes_.size());
  ImageRGBA shown = glare.composed_cd_m2;
  std::vector<GlareFrameReport> reports;
  for (std::size_t e = 0; e < stereo_eyes_.size(); ++e) {
    StereoEye& eye = *stereo_eyes_[e];
    EyeIntervalGlare& inputs = glare.eyes[e];
    const PixelRect& view = eye.view.viewport;
    const ImageRGBA seen = crop_view(glare.seen_cd_m2(), view);
    std::vector<GlareLayer> layers;
    for (const GlareLayer& layer : glare.layers)
      layers.push_back({crop_view(layer.image_cd_m2, view), layer.mode, layer.keep_peak});
    const double field_cd_m2 = mean_luminance(seen);
    std::vector<GlareFrameReport> eye_reports;
    const auto glare_of = [&](const ImageRGBA& scene_cd_m2, std::optional<double> field) {
      if (!layers.empty())
        return apply_layered_glare(eye.glare, scene_cd_m2, layers, time_s, inputs.gaze, &eye_reports, field);
      GlareFrameReport report;
      ImageRGBA glared =
          eye.glare.apply(scene_cd_m2, glare.mode, time_s, &report, inputs.gaze, field.value_or(field_cd_m2));
      eye_reports.push_back(report);
      return glared;
    };
    if (glare.perceived) {
      const GazePoint gaze = inputs.gaze.value_or(GazePoint{});
      const PerceptionResult result = eye.perception.process(seen, glare.perception, time_s, period_s_, gaze.x, gaze.y,
                                                             glare.glared ? FieldGlare(glare_of) : FieldGlare());
      inputs.adapted_cd_m2.push_back(result.adapted_luminance_cd_m2);
      paste_view(shown, result.image, view);
      if (k + 1 == glare.frames_needed)
        eye.perception.see(result.frame_luminance_cd_m2, glare.first_flip_s, period_s_, glare.frames_needed,
                           glare.stimulus_frames);
    } else {
      paste_view(shown, glare_of(seen, std::nullopt), view);
    }
    for (const GlareFrameReport& report : eye_reports)
      if (report.pupil_diameter_mm > 0.0) {
        inputs.pupil_sum_mm += report.pupil_diameter_mm;
        ++inputs.pupil_frames;
      }
    reports.insert(reports.end(), eye_reports.begin(), eye_reports.end());
  }
  // As the mono path keeps them (trial_glare.cpp): frame 0 exact, the rest at half precision.
  glare.frames.push_back(changed_region(glare.composed_cd_m2, shown,
                                        k == 0 ? RegionPrecision::exact : RegionPrecision::half_rgb));
  if (k == 0 && preview_frame_ && preview_frame_->reports.empty()) preview_frame_->reports = reports;
  count_glare_reports(glare, reports);
  glare.frame_compute_s.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  display_.make_current();  // a GL glare backend works in a context of its own
}

void SessionLoop::log_stereo_eyes(const TrialPlan& plan, const IntervalGlare& glare) {
  if (stereo_eyes_.empty() || !glare.active) return;
  std::string text = "trial " + std::to_string(plan.trial_index) + " (" + glare.modes_label + "):";
  for (std::size_t e = 0; e < stereo_eyes_.size() && e < glare.eyes.size(); ++e) {
    const EyeIntervalGlare& eye = glare.eyes[e];
    text += (e == 0 ? " " : "; ") + eye_label(*stereo_eyes_[e]) + ": pupil ";
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
  store_.log_event(session_id_, clock_.now_s(), "stereo_eyes", text);
}

}  // namespace glarelab

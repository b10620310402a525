// Drawing and presenting a trial's flips: where the scenes go, what a flip draws, the background
// and text screens around the stimulus, and how each flip is recorded (late ones logged).
#include <sstream>
#include <string>
#include <vector>

#include "runner/session/session_loop.h"
#include "runner/session/trial_schedule.h"

namespace glarelab {

std::vector<Placement> SessionLoop::layout(const TrialPlan& plan) const {
  std::vector<PixelRect> sizes;
  for (const auto& scene_name : plan.scenes) {
    const auto& scene = prepared_.scenes->get(scene_name);
    sizes.push_back({0, 0, scene.image_cd_m2.width_px, scene.image_cd_m2.height_px});
  }
  std::vector<PixelRect> columns;
  // The scenes in each eye's view as on a display of its size (a mono display's one eye: the
  // whole frame), the first eye's placements first.
  const auto rects = stereo_layout(glare_.eye_views(), sizes, &columns, stimulus_gap_px(prepared_.experiment.display));
  std::vector<Placement> placements;
  for (std::size_t r = 0; r < rects.size(); ++r) {
    const std::size_t i = r % plan.scenes.size();
    placements.push_back({&textures_.at(plan.scenes[i]), plan.scene_scale.empty() ? 1.0 : plan.scene_scale[i],
                          rects[r], columns[r]});
  }
  return placements;
}

namespace {

bool same_rect(const PixelRect& a, const PixelRect& b) {
  return a.x_px == b.x_px && a.y_px == b.y_px && a.width_px == b.width_px && a.height_px == b.height_px;
}

// The overlays that draw into `box` (each draws its rectangle within its clip), clipped to it.
std::vector<Placement> overlays_within(const std::vector<Placement>& overlays, const PixelRect& box) {
  std::vector<Placement> within;
  for (Placement overlay : overlays) {
    if (intersection(intersection(overlay.rect, overlay.clip), box).empty()) continue;
    overlay.clip = intersection(overlay.clip, box);
    within.push_back(overlay);
  }
  return within;
}

bool same_placements(const std::vector<Placement>& a, const std::vector<Placement>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].scene != b[i].scene || a[i].scale_cd_m2 != b[i].scale_cd_m2 || !same_rect(a[i].rect, b[i].rect) ||
        !same_rect(a[i].clip, b[i].clip))
      return false;
  return true;
}

}  // namespace

void SessionLoop::draw(const std::vector<Placement>& placements, const GlaredRegion* glared,
                       const std::vector<Placement>& overlays) {
  if (fast_forward_) return;
  // A flip of the frame the stimulus framebuffer already holds (the same scenes, glared region and
  // overlays, nothing written to it since): only the display encoding is redone (encode(): not
  // even that where the display keeps its presented frame), as between the flips of a blank
  // phase. The framebuffer's values are the same either way. A static glare interval shows one
  // region at every flip; a dynamic one a new region each flip.
  const std::uint64_t glared_serial = glared != nullptr ? glared->serial : 0;
  if ((glared == nullptr || glared_serial != 0) && drawn_ && drawn_->generation == renderer_.stimulus_generation() &&
      drawn_->glared_serial == glared_serial && same_placements(drawn_->placements, placements) &&
      same_placements(drawn_->overlays, overlays)) {
    encode();
    return;
  }
  const PixelRect glared_box =
      glared != nullptr ? PixelRect{glared->x0_px, glared->y0_px, glared->width_px, glared->height_px} : PixelRect{};
  const auto replace_region = [&] {
    if (!glared->gpu_parts.empty()) {
      for (const GlaredRegion::GpuPart& part : glared->gpu_parts)
        renderer_.replace_stimulus_region_from_buffer(part.frame->buffer(), part.view.x_px, part.view.y_px,
                                                      part.view.width_px, part.view.height_px);
    } else if (!glared->half_rgb.empty())
      renderer_.replace_stimulus_region_half_rgb(glared->half_rgb, glared->x0_px, glared->y0_px, glared->width_px,
                                                 glared->height_px);
    else
      renderer_.replace_stimulus_region_bottom_up(glared->exact_rgba, glared->x0_px, glared->y0_px, glared->width_px,
                                                  glared->height_px);
  };
  // A dynamic glare flip: the same scenes and overlays, a new glared region in the last one's
  // rectangle. The framebuffer then differs from what compose, the region and the overlays would
  // make only inside that rectangle, which the new region overwrites whole: the compose is left
  // out, and the overlays are blended again inside the rectangle only (outside it the frame
  // already holds them, and blending twice would darken it). The encode then redoes only the
  // rectangle where the display keeps its frame (FrameRenderer::encode_changes_to_display).
  // When the region drawn last is the one this region was compared with when it was made (the
  // interval's frame before it, GlaredRegion::changed_since_previous), the framebuffer already holds
  // this region's values outside the rectangle where the two differ (after an exact frame 0, values
  // that round to them): only that rectangle is written, blended with the overlays and encoded (in
  // the demo about a third of the frame: the dynamic lamp's side).
  // Overlays placed for the display, repeated in each eye's view.
  const std::vector<Placement> placed_overlays = glare_.eye_overlays(overlays);
  if (glared != nullptr && glared_serial != 0 && drawn_ && drawn_->glared_serial != 0 &&
      drawn_->generation == renderer_.stimulus_generation() && same_rect(drawn_->glared_box, glared_box) &&
      same_placements(drawn_->placements, placements) && same_placements(drawn_->overlays, overlays)) {
    const bool follows_drawn = glared->previous_serial != 0 && glared->previous_serial == drawn_->glared_serial &&
                               !glared->half_rgb.empty();
    const PixelRect rewritten = follows_drawn ? glared->changed_since_previous : glared_box;
    if (follows_drawn)
      renderer_.replace_stimulus_region_half_rgb_part(glared->half_rgb, glared->x0_px, glared->y0_px,
                                                      glared->width_px, glared->height_px, rewritten);
    else
      replace_region();
    const std::vector<Placement> within = overlays_within(placed_overlays, rewritten);
    if (!within.empty()) renderer_.compose_overlay(within);
    drawn_->generation = renderer_.stimulus_generation();
    drawn_->glared_serial = glared_serial;
    encode();
    return;
  }
  drawn_.reset();
  // A glared region held on the host that covers the whole frame replaces every value the compose
  // would write (alpha too: an exact region's is the composed frame's, a half region's 1, as the
  // compose's), so the compose is left out: at a glare trial's onset in the demo, whose veil
  // reaches the whole display, about a third of the flip's drawing.
  const bool region_covers_frame = glared != nullptr && glared->gpu_parts.empty() && glared->x0_px == 0 &&
                                   glared->y0_px == 0 && glared->width_px == renderer_.width_px() &&
                                   glared->height_px == renderer_.height_px();
  if (!region_covers_frame) renderer_.compose(placements, prepared_.experiment.display.background_cd_m2);
  if (glared != nullptr) replace_region();
  if (!placed_overlays.empty()) renderer_.compose_overlay(placed_overlays);
  if (glared == nullptr || glared_serial != 0)
    drawn_ = DrawnFrame{renderer_.stimulus_generation(), placements, overlays, glared_serial, glared_box};
  encode();
}

void SessionLoop::encode() {
  if (fast_forward_) return;
  // Only this function writes the display's framebuffer during a session, and the encoding of a
  // pixel is a function of its stimulus value and position (and the session's fixed display
  // settings): an offscreen buffer, which keeps what was encoded into it, needs only the pixels
  // written since the last encode (none for an unchanged stimulus). A window's back buffer is
  // encoded whole at every flip.
  if (display_.keeps_presented_frame())
    renderer_.encode_changes_to_display(prepared_.experiment.display);
  else
    renderer_.encode_to_display(prepared_.experiment.display);
}

TrialPlan SessionLoop::interval_plan(const TrialPlan& plan, int interval) const {
  if (!sequential_) return plan;
  const auto i = static_cast<std::size_t>(interval);
  TrialPlan one = plan;
  one.positions = {plan.positions.at(i)};
  one.scenes = {plan.scenes.at(i)};
  one.scene_scale = plan.scene_scale.empty() ? std::vector<double>{} : std::vector<double>{plan.scene_scale.at(i)};
  one.position_glare =
      plan.position_glare.empty() ? std::vector<std::string>{} : std::vector<std::string>{plan.position_glare.at(i)};
  return one;
}

void SessionLoop::record_flip(TrialRun& run, const PhaseFlip& phase, double scheduled_s, double flip_s, bool dropped,
                              std::optional<double> gaze_age_s) {
  FrameRecord record;
  record.frame_index = phase.stimulus_frame >= 0 ? phase.stimulus_frame : -(++run.other_flips);
  record.scheduled_s = scheduled_s;
  record.flip_s = flip_s;
  record.dropped = dropped;
  record.gaze_age_s = gaze_age_s;
  run.frames.push_back(record);
  run.phases.push_back(phase);
}

void SessionLoop::log_late_flip(const TrialPlan& plan, double flip_s, const std::string& which, double interval_s) {
  // Held for the trial's commit (trial_commit.cpp): a synced write here, between two flips, would
  // make the next flip late too.
  events_with_commit_.push_back({flip_s, "dropped_frame",
                                 "trial " + std::to_string(plan.trial_index) + " " + which + ": " +
                                     std::to_string(1000.0 * interval_s) + " ms since the previous flip"});
}

void SessionLoop::log_late_onset(const TrialPlan& plan, double flip_s, const LateOnset& late) {
  // Held for the commit as a dropped frame's event is: the onset's interval, its likely cause and
  // the session's own work meanwhile, so a reader can tell a stall from a wait.
  events_with_commit_.push_back({flip_s, "late_onset", late.describe(plan.trial_index)});
}

bool SessionLoop::present_timed_blank(const TrialPlan& plan, TrialRun& run, FlipPhase phase, int frames,
                                      const std::vector<Placement>& overlays, bool continues_blank) {
  double start_s = 0.0;
  for (int k = 0; k < frames; ++k) {
    // The stimulus framebuffer keeps the frame between these flips: later ones only re-encode it
    // (a window's back buffer is not kept across a swap).
    if (k == 0)
      draw({}, nullptr, overlays);
    else
      encode();
    const double flip_s = present();
    after_flip(flip_s);
    if (k == 0) start_s = flip_s;
    if (k == 0 && continues_blank) {
      timing_.on_flip(flip_s, plan.trial_index, -1);  // the time since the last flip, not checked
      record_flip(run, {phase, -1, -1}, flip_s, flip_s, false);
      if (prepared_.observer == nullptr)
        ignore_keys(plan, std::string("pressed during the ") + to_string(phase));
      else
        check_interrupt();
      if (aborted_) return false;
      continue;
    }
    const std::optional<double> late_s = timing_.on_timed_flip(flip_s);
    if (late_s) log_late_flip(plan, flip_s, std::string(to_string(phase)) + " flip", *late_s);
    record_flip(run, {phase, -1, -1}, start_s + k * period_s_, flip_s, late_s.has_value());
    if (prepared_.observer == nullptr)
      ignore_keys(plan, std::string("pressed during the ") + to_string(phase));
    else
      check_interrupt();
    if (aborted_) return false;
  }
  return true;
}

bool SessionLoop::show_screen(const TrialPlan& plan, const ScreenText& screen, TrialRun& run) {
  const std::vector<Placement> text = overlays_.centred_text(screen.text);
  const int minimum_flips = prepared_.experiment.presentation.screen_min.frames;
  int flips = 0;
  double first_flip_s = 0.0, last_flip_s = 0.0;
  bool proceed = false;
  while (!proceed) {
    if (flips == 0)
      draw({}, nullptr, text);
    else
      encode();
    last_flip_s = present();
    timing_.on_flip(last_flip_s, plan.trial_index, -1);
    after_flip(last_flip_s);
    if (flips++ == 0) first_flip_s = last_flip_s;
    record_flip(run, {FlipPhase::screen, -1, -1}, last_flip_s, last_flip_s, false);
    const bool long_enough = flips >= minimum_flips;
    if (prepared_.observer != nullptr) {
      check_interrupt();
      proceed = long_enough;
    } else {
      check_interrupt();
      if (!aborted_ && display_.close_requested()) {
        aborted_ = true;
        abort_reason_ = display_.close_reason();
      }
      for (const std::string& key : aborted_ ? std::vector<std::string>{} : display_.poll_keys()) {
        if (key == "escape") {
          aborted_ = true;
          abort_reason_ = "Escape pressed";
          break;
        }
        if ((key == "space" || key == "enter") && long_enough) {
          proceed = true;
          continue;
        }
        store_.log_event(session_id_, clock_.now_s(), "ignored_key",
                         "trial " + std::to_string(plan.trial_index) + " " + screen.kind + " screen: key '" + key +
                             "' " + (key == "space" || key == "enter" ? "before the screen's minimum duration"
                                                                      : "does not continue (Space or Enter)"));
      }
      if (!aborted_ && device_ != nullptr) {
        bool unplugged = false;
        proceed = device_->continues_screen(plan, screen.kind, long_enough, &unplugged) || proceed;
        if (unplugged) pause_for_response_device(plan.trial_index);
      }
      if (!aborted_ && controllers_ != nullptr) {
        proceed = controllers_->continues_screen(plan, screen.kind, first_flip_s, long_enough) || proceed;
      }
    }
    if (aborted_) return false;
  }
  std::ostringstream message;
  message << "trial " << plan.trial_index << ", " << screen.kind << ": '" << first_words(screen.text) << "' shown "
          << flips << " flips (" << last_flip_s - first_flip_s + period_s_ << " s)";
  store_.log_event(session_id_, last_flip_s, "screen", message.str());
  return true;
}

}  // namespace glarelab

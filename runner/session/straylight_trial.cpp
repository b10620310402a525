// A straylight trial (TrialPlan::straylight, docs/STRAYLIGHT.md): its frames are the ring and the
// compensation light drawn through the session's frame path (composed, encoded, flipped and stored
// like any stimulus frame). Within each cycle of frames_per_cycle frames the ring is on for the
// first half and the compensation light, on one half of the test field, for the second: the
// square wave and its counterphase. Nothing else is lit; no glare or perception stage is applied,
// since the straylight measured is the participant's own.
#include <cstdio>
#include <filesystem>

#include "core/exr_io.h"
#include "runner/session/session_loop.h"
#include "runner/session/straylight_session.h"

namespace glarelab {

void SessionLoop::upload_straylight_stimulus() {
  if (prepared_.experiment.procedure != "straylight") return;
  const StraylightImages images = straylight_images(prepared_.experiment.display, prepared_.experiment.straylight);
  straylight_textures_.push_back(renderer_.upload(images.ring));
  straylight_textures_.push_back(renderer_.upload(images.left_half));
  straylight_textures_.push_back(renderer_.upload(images.right_half));
  const int width = images.ring.width_px, height = images.ring.height_px;
  straylight_rect_ = {(display_.width_px() - width) / 2, (display_.height_px() - height) / 2, width, height};
}

std::vector<Placement> SessionLoop::straylight_frame(const TrialPlan& plan, int frame_in_interval) const {
  const StraylightStimulusPlan& shown = *plan.straylight;
  const bool ring_on = straylight_ring_on(frame_in_interval, shown.frames_per_cycle);
  const SceneTexture& texture = straylight_textures_.at(ring_on ? 0 : shown.compensation_left ? 1 : 2);
  return {Placement{&texture, ring_on ? shown.ring_luminance_cd_m2 : shown.compensation_cd_m2, straylight_rect_,
                    straylight_rect_}};
}

void SessionLoop::save_straylight_cycle_frame(const TrialPlan& plan, int frame_in_interval) {
  if (save_frames_dir_.empty() || fast_forward_ || !plan.straylight ||
      frame_in_interval >= plan.straylight->frames_per_cycle)
    return;
  char name[64];
  std::snprintf(name, sizeof name, "trial_%04d_drive_%02d.exr", plan.trial_index, frame_in_interval);
  const auto saving_start = std::chrono::steady_clock::now();
  frame_writer_->write((std::filesystem::path(save_frames_dir_) / name).string(), renderer_.read_display(),
                       /*as_scene=*/false);
  timing_.add_work(FlipWork::recording,
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - saving_start).count());
}

IntervalGlare SessionLoop::begin_straylight(const TrialPlan& plan, int flips_before) {
  // Inactive, as for a real stimulus (real_stimulus_trial.cpp): the drawn frame is shown as it is.
  IntervalGlare interval;
  interval.period_s = period_s_;
  interval.first_flip_s = clock_.now_s() + (1 + flips_before) * period_s_;
  interval.stimulus_frames = plan.stimulus_frames;
  interval.modes_label = "straylight measurement (no glare: the participant's own is measured)";
  if (capture_.captures(plan) && !capture_.frame) {
    capture_.frame.emplace();
    capture_.frame->plan = plan;
    capture_.frame->time_s = interval.first_flip_s;
    capture_.frame->glare_label = interval.modes_label;
  }
  return interval;
}

}  // namespace glarelab

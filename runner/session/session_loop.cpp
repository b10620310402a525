// The trial loop's setup for a session (glare setup logged, every scene uploaded once) and the
// pupil calibration before its first trial.
#include "runner/session/session_loop.h"


namespace glarelab {

SessionLoop::SessionLoop(PreparedSession& prepared, DisplayBackend& display, SessionClock& clock, ResultStore& store,
                         std::int64_t session_id, TrackerSession& tracker, RealTimePacer* pacer)
    : tracker_(tracker),
      pacer_(pacer),
      prepared_(prepared),
      display_(display),
      clock_(clock),
      store_(store),
      session_id_(session_id),
      renderer_(display.width_px(), display.height_px()),
      period_s_(1.0 / display.refresh_hz()),
      composition_(display.width_px(), display.height_px()),
      timing_(display.refresh_hz()),
      glare_(prepared, renderer_, display, clock, store, session_id, tracker, capture_),
      overlays_(renderer_, prepared.experiment),
      // Ratings and adjustment never read `layout`: it keeps its default there.
      sequential_(prepared.experiment.forced_choice.layout == "sequential") {
  renderer_.set_display_framebuffer(display.frame_framebuffer());
  for (const auto& [name, scene] : prepared_.scenes->scenes()) {
    const SceneTexture& texture = textures_.emplace(name, renderer_.upload(scene.image_cd_m2)).first->second;
    composition_.add_scene(texture, scene.image_cd_m2);
  }
  glare_.compose_on_cpu_where_exact(&composition_);
  upload_straylight_stimulus();
  glare_.hold_trial_events_in(&events_with_commit_);
  // Frames kept at half precision take their storage from a pool the frames of the interval before
  // hand back; for the first interval of a frame per flip it is filled now, before the first trial,
  // with storages a whole frame fits (runner/session/glared_region.h). On the virtual clock no flip
  // waits for a frame, so the pool fills as the frames need it (the same frames either way).
  if (glare_.makes_frame_sequences() && clock_.keeps_real_time())
    fill_half_storage(3 * static_cast<std::size_t>(prepared.experiment.display.width_px) *
                      static_cast<std::size_t>(prepared.experiment.display.height_px));
}

// --- tracker (runner/tracker/) ---
bool SessionLoop::calibrate_pupil() {
  for (const bool black : {true, false}) {
    tracker_.begin_calibration_phase(black);
    const double luminance_cd_m2 = black ? 0.0 : prepared_.experiment.display.peak_luminance_cd_m2;
    const double phase_start_s = clock_.now_s();
    while (clock_.now_s() - phase_start_s < tracker_.calibration_screen_s()) {
      renderer_.compose({}, luminance_cd_m2);
      encode();
      after_flip(present());
      check_interrupt();
      if (!aborted_ && display_.close_requested()) {
        aborted_ = true;
        abort_reason_ = display_.close_reason();
      }
      if (aborted_) return false;
    }
  }
  tracker_.finish_calibration(clock_.now_s());  // logged as a pupil_calibration event by the tracker logger
  return true;
}
// --- end tracker ---

}  // namespace glarelab

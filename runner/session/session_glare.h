#pragma once
// A session's glare and perception: each trial's inputs (the condition's glare modes, model, gain,
// optics and perception stages, the tracker's gaze, pupil and blinks), its intervals' frames made
// by each eye's frame engine (stimuli/frame_engine.h) and joined, how they are presented (prepared
// before onset or live) with the measured cost, and the events that report them. The session loop
// (runner/session/session_loop.h) keeps the schedule: it asks for an interval's glare before the
// fixation, for each frame before its flip, and for the reports after the timed sequence.
//
// Its member functions are defined by concern: runner/session/trial_glare.cpp (an interval's
// inputs and frames, their events), runner/session/eye_glare.cpp (each eye's part), and
// runner/session/glare_presentation.cpp (prepared or live, and the once-only records).
#include <algorithm>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/clock.h"
#include "runner/display/display_backend.h"
#include "runner/session/condition_refraction.h"
#include "runner/session/cpu_composition.h"
#include "runner/session/interval_glare.h"
#include "runner/session/session_eyes.h"
#include "runner/session/session_setup.h"
#include "runner/session/stimulus_preview.h"
#include "runner/store/result_store.h"
#include "runner/tracker/tracker_session.h"
#include "stimuli/frame_renderer.h"

namespace glarelab {

// A preview (glarelab render, runner/session/stimulus_preview.h) attached to a session, and the
// frame it captures.
struct PreviewCapture {
  const StimulusPreview* preview = nullptr;
  std::optional<PreviewFrame> frame;  // being captured: labelled when its interval begins, then captured
  std::vector<PreviewFrame> captured;  // complete, in the order the session showed them
  // Whether `plan` is a trial of a previewed condition not captured yet.
  bool captures(const TrialPlan& plan) const {
    if (preview == nullptr) return false;
    const auto same = [&](const std::string& name) { return name == plan.condition_name; };
    return std::any_of(preview->conditions.begin(), preview->conditions.end(), same) &&
           std::none_of(captured.begin(), captured.end(),
                        [&](const PreviewFrame& done) { return same(done.plan.condition_name); });
  }
  bool complete() const { return preview != nullptr && captured.size() == preview->conditions.size(); }
  // Whether the next capture is the last one (the session ends at it).
  bool captures_last() const { return preview != nullptr && captured.size() + 1 == preview->conditions.size(); }
};

// An event of a trial held to be written with the trial's commit, beside the next onset
// (runner/session/trial_commit.cpp), rather than by a synced write on the display's thread between
// the trial's flips or before the next onset.
struct HeldEvent {
  double at_s;
  std::string kind, message;
};

class SessionGlare {
 public:
  // A trial's own events (glare skipped, its window, gaze latency, stereo eyes, a live layout taken
  // back to prepared) go into `held` from now on, written with the trial's commit.
  void hold_trial_events_in(std::vector<HeldEvent>* held) { held_events_ = held; }

  // Logs the glare setup (backend and frame engine, the eye's inputs, the observer's optics per
  // condition, stereo eyes). `renderer` composes the scenes the glare is applied to.
  SessionGlare(const PreparedSession& prepared, FrameRenderer& renderer, DisplayBackend& display, SessionClock& clock,
               ResultStore& store, std::int64_t session_id, TrackerSession& tracker, PreviewCapture& capture);

  // Intervals begun on the display's thread compose their frame on the CPU by `composition` where
  // it gives GL's frame bit for bit (CpuComposition::exact), not in GL read back: no read-back of
  // the composed frame. `composition` must outlive this object.
  void compose_on_cpu_where_exact(const CpuComposition* composition) { exact_composition_ = composition; }

  // --- an interval's inputs and frames (runner/session/trial_glare.cpp) ---
  // The interval's glare set up before the fixation: modes, composed frame, what each eye sees of
  // it, and tracker inputs. `flips_before`: timed flips between now and the interval's first
  // stimulus frame (fixation, interval 1).
  IntervalGlare begin_interval(const TrialPlan& plan, const std::vector<Placement>& placements, int flips_before);
  // The same on a worker beside the display's flips (runner/session/trial_ahead.cpp), its first
  // stimulus frame flipping at `first_flip_s`: the scenes composed by `composition` on the CPU (the
  // GL composition's frame bit for bit, runner/session/cpu_composition.h), the display's context
  // never made current. Only when computes_off_display_thread() said so, composition.exact(placements),
  // no tracker runs and no preview captures, and nothing else asks the eyes for frames meanwhile.
  IntervalGlare begin_interval_off_display(const TrialPlan& plan, const std::vector<Placement>& placements,
                                           double first_flip_s, const CpuComposition& composition);
  // Whether the interval's frames are all computed before onset (prepared presentation; glare and
  // perception frames alike: live ones are computed in the order they flip, as prepared ones are).
  bool prepared_before_onset(const IntervalGlare& glare) const;
  // Every frame of the interval before onset (the first `frames` with frames >= 0); stops, returning
  // false, when `interrupted` says so (checked before each frame: preparing a trial's frames can
  // take seconds on a CPU). display_thread false: on a worker beside the display's flips
  // (runner/session/trial_ahead.cpp), where the display's context is never made current; only
  // when computes_off_display_thread() said so, no tracker runs, and nothing else asks the eyes
  // for frames meanwhile.
  bool prepare_frames(IntervalGlare& glare, const std::function<bool()>& interrupted, int frames = -1,
                      bool display_thread = true);
  // Whether frames can be computed on a thread other than the display's: every eye's engine is the
  // CPU engine (choosing it now, on the display's thread, if no frame has yet).
  bool computes_off_display_thread();
  // Whether some condition's intervals can make a frame per flip (dynamic glare on a side, or the
  // adaptation stage), known after the setup.
  bool makes_frame_sequences() const { return frame_sequences_ || adapts_; }
  // Frame k of the interval, computed for its flip time if it is needed and not yet there: each
  // eye's part, joined.
  void compute_frame(IntervalGlare& glare, int k);
  // Whether interval frames count as live ones (their late flips reviewed) and whether glare
  // flips' drawing is still timed for the presentation to settle.
  bool shown_live(const IntervalGlare& glare) const;
  bool presentation_settled(const IntervalGlare& glare) const;
  // After the timed sequence: the interval's events (skips, gaze window, gaze latency, stereo
  // eyes), the presentation settled or reviewed, the perception stages' cost.
  void report_interval(const TrialPlan& plan, const IntervalGlare& glare);

  // --- each eye's view (runner/session/eye_glare.cpp) ---
  std::vector<EyeView> eye_views() const;
  // Overlays placed for the whole display, repeated in each eye's view (clipped to it).
  std::vector<Placement> eye_overlays(const std::vector<Placement>& overlays) const;

 private:
  // runner/session/trial_glare.cpp
  // A condition's optics in an interval: its refraction (nullptr when the observer's optics are not
  // modelled), whether its spectacles warp the frame and whether the depth of field blurs it.
  struct ConditionOptics {
    const ConditionRefraction* refraction = nullptr;
    bool spectacles = false;
    bool depth_of_field = false;
  };
  ConditionOptics condition_optics(const TrialPlan& plan) const;
  // begin_interval's work, composing in GL on the display's thread (`composition` nullptr) or on
  // the CPU beside it.
  IntervalGlare begin_interval_at(const TrialPlan& plan, const std::vector<Placement>& placements, double first_flip_s,
                                  const CpuComposition* composition);
  // The placements composed over `background_cd_m2` and read back (row 0 at the top).
  ImageRGBA composed(const std::vector<Placement>& placements, double background_cd_m2,
                     const CpuComposition* composition);
  // The interval's composed frame and, for each eye, its view of it (and of each position's layer
  // when the sides differ, `position_modes`) as it reaches that eye through the optics.
  void see_through_optics(IntervalGlare& glare, const TrialPlan& plan, const std::vector<Placement>& placements,
                          const ConditionOptics& optics, const std::vector<GlareMode>& position_modes,
                          const CpuComposition* composition);
  void log_interval_glare(const TrialPlan& plan, const IntervalGlare& glare);
  const ConditionRow& condition_row(const TrialPlan& plan) const;

  // runner/session/glare_presentation.cpp
  enum class GlarePresentation { prepared, live };
  // How glare intervals are presented: [glare] presentation "live" or "prepared" for all; "auto"
  // settles each glare layout (the interval's glare modes, whatever their sides: a dynamic source
  // beside a static one costs more than one beside a control) on the first interval of it,
  // prepared until then.
  GlarePresentation presentation_for(const IntervalGlare& glare) const;
  // Once, after the first glare interval: prepared or live from then on, with the measured cost.
  void settle_glare_presentation(const TrialPlan& plan, const IntervalGlare& glare);
  // "auto": a layout settled live whose trial dropped a glare frame is prepared from the next
  // trial on, and a presentation_mode event says so, with the frames' measured costs.
  void review_live_presentation(const TrialPlan& plan, const IntervalGlare& glare);
  // Once per session: the glare backend and frame engine (what and why), where the eye's inputs
  // come from and, when the observer's optics are modelled, an 'observer_refraction' event per
  // condition.
  void log_glare_setup();
  // Once, after the first interval with perception stages: a 'perception_stages' event with the
  // settings and the measured cost per frame.
  void log_perception_stages(const TrialPlan& plan, const IntervalGlare& glare);

  // runner/session/eye_glare.cpp
  // compute_frame's work without making the display's context current after it; true when it
  // computed the frame.
  bool make_frame(IntervalGlare& glare, int k);
  // Each eye's pupil and blinks from the tracker, for its glare stage.
  void feed_tracker_inputs();
  // Each eye's gaze for a frame flipping at flip_s, normalised in its view: the latest, or with
  // latency compensation the gaze extrapolated to that flip.
  void update_glare_gaze(IntervalGlare& glare, double flip_s);
  // Section 5.1's adaptation luminance of eye `e`'s part of a frame at its gaze (its view's centre
  // without one).
  double adaptation_luminance(std::size_t e, const IntervalGlare& glare, const ImageRGBA& eye_part_cd_m2) const;
  // The eyes seeing the interval's frames shown without stages: their parts of `composed_cd_m2`, or
  // with nullptr what each sees of the interval's frame through the optics.
  void see_interval(const IntervalGlare& glare, const ImageRGBA* composed_cd_m2);
  // A preview passing by: each eye sees the interval's frames as computing them would have made it.
  void record_interval(const IntervalGlare& glare, const ImageRGBA& composed_cd_m2);
  EyeFrame eye_frame(std::size_t e, IntervalGlare& glare, int k, std::vector<GlareFrameReport>& reports);
  // After the timed sequence, where an eye's frame engine is the GL one: a `read_backs` event with
  // what frame 0 of the interval read back (core/gl/read_back.h) and what was read back after it.
  void log_read_backs(const TrialPlan& plan, const IntervalGlare& glare);
  // Once per session, stereo only: a 'stereo' event with each eye's view, seed and inputs.
  void log_stereo_setup();
  // Stereo only: the interval's stereo_eyes event (each eye's pupil, gaze and adapted luminance).
  void log_stereo_eyes(const TrialPlan& plan, const IntervalGlare& glare);

  // A trial's own event: held for its commit when hold_trial_events_in was called, else written now.
  void log_trial_event(double at_s, const std::string& kind, std::string message);
  std::vector<HeldEvent>* held_events_ = nullptr;
  const CpuComposition* exact_composition_ = nullptr;  // compose_on_cpu_where_exact

  const PreparedSession& prepared_;
  FrameRenderer& renderer_;
  DisplayBackend& display_;
  SessionClock& clock_;
  ResultStore& store_;
  std::int64_t session_id_;
  TrackerSession& tracker_;
  PreviewCapture& capture_;
  double period_s_;
  // Live glare needs a frame's glare computed and drawn within this fraction of the refresh
  // period; the rest is the margin for the flip and the machine's other work.
  static constexpr double kLiveBudgetFraction = 0.75;
  std::map<std::string, GlarePresentation> settled_presentations_;  // by glare_layout()
  bool presentation_logged_ = false;  // "live" / "prepared" as asked: said once
  // The session's eyes (runner/session/session_eyes.h): one on a mono display, left and right in
  // stereo, each with its frame engine.
  std::vector<std::unique_ptr<SessionEye>> eyes_;
  // Some condition has adaptation on, so every interval's frames are shown to the eyes.
  bool adapts_ = false;
  // Some condition has glare or perception stages: the eyes' engines were chosen at the setup.
  // Otherwise no frame is ever computed, and no engine is made.
  bool engines_chosen_ = false;
  bool perception_logged_ = false;
  bool frame_sequences_ = false;  // some condition has dynamic glare (log_glare_setup)
  // Each condition's refraction by condition name (runner/session/condition_refraction.h); empty
  // when the experiment does not model the observer's optics.
  std::map<std::string, ConditionRefraction> condition_refractions_;
};

}  // namespace glarelab

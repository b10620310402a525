#pragma once
// One interval's glare in a session (runner/session/trial_glare.cpp): what its frames need (the
// modes, the composed frame, its layers when the sides differ) and what computing them reported,
// gathered for the trial's events. Frames are computed before onset ("prepared") or each just
// before its flip ("live": the gaze window follows the gaze frame by frame).
#include <algorithm>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/gl/read_back.h"
#include "core/image.h"
#include "core/perception_settings.h"
#include "runner/session/glared_region.h"
#include "runner/tracker/tracker_session.h"
#include "stimuli/glare_stage.h"
#include "stimuli/position_glare.h"

namespace glarelab {

// One eye's part of an interval (runner/session/eye_glare.cpp): what it sees of the interval's
// frame, its gaze in its own view, and what its frames reported.
struct EyeIntervalGlare {
  // The composed frame's part in the eye's view; unset where the view is the whole frame (mono).
  std::optional<ImageRGBA> view_cd_m2;
  // That part as it reaches the eye through the condition's spectacles (the frame warped by the
  // lens, runner/session/condition_refraction.h) and blurred by the depth of its points, the eye
  // accommodated on its own view's centre (runner/session/condition_depth_of_field.h); unset
  // without either.
  std::optional<ImageRGBA> through_spectacles;
  std::vector<GlareLayer> layers;  // one per position when the sides differ (its view); else empty
  StaticLayerGlare static_layers;  // the static layers' glare, kept from frame to frame
  double field_cd_m2 = 0.0;  // the seen frame's mean luminance, what the eye adapts to (once, not per frame)
  FrameFacts seen_facts;     // the seen frame's, found on its first glared frame (stimuli/glare_stage.h)
  std::optional<GazePoint> gaze;       // normalised in the eye's view
  std::optional<TrackerGaze> tracked;  // the tracker's gaze the eye's window is placed at
  double pupil_sum_mm = 0.0;  // over the eye's wave-optics frames (report.pupil_diameter_mm > 0)
  int pupil_frames = 0;
  std::vector<double> adapted_cd_m2;  // perception: each frame's adapted luminance (Eq. 5.2)

  // What the eye sees of the interval's frame (its part of `composed_cd_m2`, through the optics).
  const ImageRGBA& seen_cd_m2(const ImageRGBA& composed_cd_m2) const {
    return through_spectacles ? *through_spectacles : view_cd_m2 ? *view_cd_m2 : composed_cd_m2;
  }
};

// What an interval's frames are made through, decided once when it begins.
enum class IntervalFrames {
  // None computed: the composed frame is shown as it is (every position control and no perception
  // stage, or a preview passing by).
  composed,
  glare,       // the glare alone
  perception,  // the perception stages, the glare (when there is any) between adaptation and acuity
};

// The glare in an interval.
enum class IntervalGlareMotion {
  none,    // every position control
  still,   // a frozen eye or an analytic model: alike on every frame
  moving,  // the eye moves from frame to frame (a dynamic mode on a model with a moving eye)
};

struct IntervalGlare {
  IntervalFrames made = IntervalFrames::composed;
  IntervalGlareMotion motion = IntervalGlareMotion::none;
  bool computed() const { return made != IntervalFrames::composed; }
  bool perceived() const { return made == IntervalFrames::perception; }
  bool glared() const { return motion != IntervalGlareMotion::none; }
  // The condition's perception stages (stimuli/session_perception.h).
  PerceptionSettings perception;
  GlareMode mode = GlareMode::control;
  std::vector<GlareMode> layer_modes;  // each position's mode when the sides differ; else empty
  ImageRGBA composed_cd_m2;
  int frames_needed = 1;      // dynamic (or adapting): every stimulus frame; static: one serves all
  int stimulus_frames = 1;    // the interval's stimulus frames
  double first_flip_s = 0.0;  // session time of the interval's first stimulus flip
  double period_s = 0.0;
  std::string modes_label;    // "dynamic", or "left dynamic, right control"
  // Computed so far (frame k at index k): frame 0 exact, the others at half precision
  // (runner/session/glared_region.h).
  std::vector<GlaredRegion> frames;
  // Live with a tracker: the session time of the gaze sample frame k's window was placed at (its
  // oldest eye's).
  std::vector<std::optional<double>> gaze_time_s;

  // Reports, for the trial's glare_skipped / glare_window / gaze_latency events.
  int applications = 0, skipped = 0, gratings_hidden = 0, closed = 0;
  std::string skip_reason;
  double smallest_pupil_mm = 1e9;
  std::optional<GazeWindow> window;  // the first eye's
  std::vector<double> gaze_to_flip_s;  // live: each frame's flip time minus its gaze sample's time
  int live_frames_shown = 0, live_frames_dropped = 0;  // live: stimulus flips, and those that came late
  std::vector<double> frame_compute_s;  // wall time spent computing each frame
  // Until the session has settled how glare is presented: wall time drawing each glare flip (the
  // region put in, overlays, the encode, the GL work finished), the rest of a live frame's cost.
  std::vector<double> frame_draw_s;
  std::vector<EyeIntervalGlare> eyes;  // one per eye of the session (runner/session/session_eyes.h)
  // Read-backs from the GPU (core/gl/read_back.h): those computing frame 0, and the process's tally
  // when it was done, which the interval's later frames and flips are counted from.
  gl::ReadBackTally read_backs_first_frame;
  std::optional<gl::ReadBackTally> read_backs_after_first_from;
  // The GL engine: each GPU stage's time summed over the frames that timed it (EyeFrame::gpu_stages_s),
  // in the order the stages first ran, and how many frames each sum holds.
  struct GpuStageSum {
    std::string stage;
    double seconds = 0.0;
    int frames = 0;
  };
  std::vector<GpuStageSum> gpu_stage_sums;
  void add_gpu_stage_times(const std::vector<std::pair<std::string, double>>& stages_s) {
    // A pair, not a structured binding: the lambda below captures the stage's name, which clang
    // accepts from a structured binding only from version 16 (the fuzz and sanitizer builds use 14).
    for (const std::pair<std::string, double>& stage_s : stages_s) {
      const std::string& stage = stage_s.first;
      auto sum = std::find_if(gpu_stage_sums.begin(), gpu_stage_sums.end(),
                              [&stage](const GpuStageSum& s) { return s.stage == stage; });
      if (sum == gpu_stage_sums.end()) sum = gpu_stage_sums.insert(gpu_stage_sums.end(), GpuStageSum{stage});
      sum->seconds += stage_s.second;
      ++sum->frames;
    }
  }

  double frame_time_s(int k) const { return first_flip_s + k * period_s; }
  std::optional<double> gaze_time_of(int k) const {
    if (k < 0 || static_cast<std::size_t>(k) >= gaze_time_s.size()) return std::nullopt;
    return gaze_time_s[static_cast<std::size_t>(k)];
  }
  // The frame shown at stimulus frame k of the interval: frame k, or the last one computed.
  const GlaredRegion* shown(int k) const {
    if (!computed() || frames.empty()) return nullptr;
    return &frames[std::min<std::size_t>(static_cast<std::size_t>(k), frames.size() - 1)];
  }
};

// Counts a frame's glare reports into the interval's (applications, skips, held blinks, ...).
void count_glare_reports(IntervalGlare& glare, const std::vector<GlareFrameReport>& reports);

}  // namespace glarelab

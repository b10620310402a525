#pragma once
// A session run as a preview (glarelab render): the trials before the first one of a condition
// run as they would (same clock, same eye history, glare recorded but not computed, nothing
// stored), and that trial's first stimulus frame is captured, after glare and with its overlays,
// instead of being shown to anyone. So the preview is the frame a seeded session shows, by
// construction, and any procedure can be previewed at a chosen intensity or setting. Several
// conditions are captured in one pass: the session runs on, exactly as it would, until the last
// of them is captured (no override then: one would change every trial after it).
#include <optional>
#include <string>
#include <vector>

#include "core/image.h"
#include "glare/glare_spec.h"
#include "protocols/trial_plan.h"
#include "stimuli/glare_stage.h"

namespace glarelab {

struct StimulusPreview {
  // The first trial of each of these conditions is captured. The overrides below apply to one
  // condition only.
  std::vector<std::string> conditions;
  // Staircase or QUEST: one value (the comparison's peak, cd/m2); adjustment: the left and right
  // spots; empty: as the procedure starts (protocols/comparison_luminance.h).
  std::vector<double> comparison_cd_m2;
  std::optional<double> time_s;     // the eye at this session time instead of the frame's own
  std::optional<GlareMode> glare;   // this mode on the whole frame instead of the condition's
};

struct PreviewFrame {
  TrialPlan plan;            // as shown (overrides applied)
  double time_s = 0.0;       // session time the glare was computed for
  ImageRGBA stimulus_cd_m2;  // the stimulus framebuffer: after glare, with the overlays (cd/m2)
  ImageRGBA display_drive;   // what the display was sent (encoded drive values 0..1)
  std::string glare_label;   // the glare shown, e.g. "dynamic" or "left dynamic, right control"
  std::vector<GlareFrameReport> reports;  // one per glare layer computed (none for control)
};

}  // namespace glarelab

#pragma once
// What one trial shows and accepts, decided before it runs, and what came of it.
#include <optional>
#include <string>
#include <vector>

namespace glarelab {

// A straylight trial (protocols/straylight_procedure.h, docs/STRAYLIGHT.md): drawn instead of
// scenes, centred on the fixation point: the ring flickering as a square wave (on for the first
// half of each cycle) and the compensation light on one half of the dark test field in
// counterphase (on for the second half).
struct StraylightStimulusPlan {
  double ring_inner_deg = 5.0;
  double ring_outer_deg = 10.0;
  double test_field_radius_deg = 2.0;
  double ring_luminance_cd_m2 = 0.0;
  double compensation_cd_m2 = 0.0;
  bool compensation_left = false;
  int frames_per_cycle = 8;
  // The display's own stray light on the test field while the ring is on: not drawn (it is the
  // display's), but a simulated participant sees it flicker with the ring.
  double display_glow_cd_m2 = 0.0;
};

struct TrialPlan {
  int trial_index = 0;  // from 0 within the session
  int block = 0;        // from 0, in the order the session runs its blocks
  std::string block_name;  // the block's name from [[blocks]]; empty without blocks
  // Text of the instruction or break screen shown before this trial (the first trial of a block,
  // or of the session); empty: no screen. The runner shows it until the observer continues.
  std::string screen_text;
  std::string procedure;       // forced_choice | staircase | quest | adjustment | rating
  std::string condition_name;
  std::string condition_json;  // the condition row plus presentation facts, as a JSON object
  std::vector<std::string> positions;  // e.g. {"left", "right"}
  std::vector<std::string> scenes;     // scene name shown at each position
  // A rating of a physical object (core/real_stimulus.h, scene "real:desk lamp"): the object's
  // name. The session then draws the instruction to look at it instead of the scene, without
  // glare or perception stages. Empty: the scenes are images.
  std::string real_stimulus;
  // The condition each position shows (forced choice rows with condition_a / condition_b columns,
  // e.g. Ritschel's dynamic, static, control); empty otherwise. The simulated observer's
  // preferences ([observer.simulated.preferences]) are between these names.
  std::vector<std::string> position_conditions;
  // The glare mode shown at each position ("dynamic", "static", "control") when the row gives one
  // per side (glare_a / glare_b); empty: the row's glare applies to the whole frame.
  std::vector<std::string> position_glare;
  // With position_glare: each glared position keeps its pre-glare peak (stimuli/position_glare.h,
  // GlareLayer::keep_peak; [procedure] glare_keeps_peak).
  bool glare_keeps_peak = false;
  // Peak luminance (cd/m2) of the source at each position: what a simulated observer compares.
  std::vector<double> source_luminance_cd_m2;
  // Factor on each position's scene (empty: all 1). Adaptive procedures scale the comparison
  // scene so that its peak is the trial's intensity in cd/m2.
  std::vector<double> scene_scale;
  // The positions whose scene the procedure scales to a luminance (staircase and QUEST: the
  // comparison; adjustment: the left and right spots); empty for fixed designs.
  // protocols/comparison_luminance.h sets them to other luminances (glarelab render).
  std::vector<int> comparison_positions;
  std::string staircase;  // the adaptive track that runs this trial; empty otherwise
  // Ratings: the mean rating of the simulated observer for this condition.
  std::optional<double> simulated_rating_mean;
  // Adjustment: the start luminances (cd/m2) of the left and right comparison spots; positions
  // are {"left", "target", "right"} and the comparison scene's scale is setting / its peak.
  std::vector<double> adjustment_start_cd_m2;
  std::vector<std::string> allowed_responses;
  std::string correct_response;  // empty when no answer is right (equal sources)
  // A PSE staircase's trial (response_rule = "pse"): the answer is which side looks brighter, with
  // no right answer; correct_response is empty.
  bool appearance_judgement = false;
  // The glare gain each position is shown with (PSE trials): the reference's row glare_gain (1
  // without the column, 0 when its glare is control), the comparison's 0 with glare_on =
  // "reference". The simulated observer's perceived brightening of glare follows it.
  std::vector<double> position_glare_gain;
  std::optional<double> intensity;
  std::optional<StraylightStimulusPlan> straylight;
  std::string question;
  int stimulus_frames = 1;
};

struct Response {
  std::string value;               // one of allowed_responses, or "abort"
  std::optional<double> response_time_s;  // from the onset flip
};

struct TrialOutcome {
  std::string response;
  std::optional<int> correct;
  std::string staircase;          // name of the staircase that ran the trial; empty otherwise
  std::optional<int> reversal;    // 1 when the trial reversed its staircase's direction, else 0
  std::optional<double> intensity;  // when the response sets it (adjustment: mean of the settings)
  std::vector<double> adjustment_settings_cd_m2;  // adjustment: left and right spot
};

}  // namespace glarelab

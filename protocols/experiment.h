#pragma once
// An experiment as described by its TOML file (and CSV condition tables), fully resolved:
// defaults filled, paths absolute, tables inlined. See docs/EXPERIMENT_FILES.md for the format.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "protocols/block_design.h"
#include "core/display_spec.h"
#include "core/errors.h"
#include "core/frame_engine_request.h"
#include "core/scene_spec.h"
#include "protocols/glare_config.h"
#include "core/observer_optics.h"
#include "protocols/analysis_config.h"
#include "protocols/perception_config.h"
#include "protocols/presentation_config.h"
#include "protocols/observer_preferences.h"
#include "protocols/quest.h"
#include "protocols/quest_plus.h"
#include "protocols/staircase.h"
#include "protocols/straylight_spec.h"

namespace glarelab {

// One row of the condition table, column order kept.
struct ConditionRow {
  std::vector<std::pair<std::string, std::string>> fields;
  SourceLocation where;
  int number = 0;  // 1-based position in the condition table, for name()
  const std::string* find(const std::string& column) const;
  std::string name() const;  // the "name" column, or "row N"
};

struct ForcedChoiceSpec {
  int alternatives = 2;
  std::string layout = "side_by_side";  // or "sequential": two intervals, one after the other
  std::string question = "Which light is brighter?";
  int stimulus_frames = 30;
  // When the file gave the duration in seconds: the value as written. stimulus_frames is then
  // the nearest whole number of refresh periods, and the runner logs the rounding.
  std::optional<double> stimulus_duration_s;
  int repetitions = 1;
  bool counterbalance_sides = true;
  std::vector<std::string> responses = {"left", "right"};
};

// One adaptive track (a staircase or a QUEST) and the condition row whose scenes it shows: the
// row's "reference" scene at its own luminance, the "comparison" scene scaled so its peak is the
// track's intensity in cd/m2 (QUEST: 10^intensity, its scale being log10 cd/m2).
// A QUEST+ or Psi track (protocols/quest_plus.h, docs/PROCEDURES.md). The first stimulus
// dimension is the comparison's peak luminance in `intensity_unit`: "db_cd_m2" (20 log10 of
// cd/m2, Watson 2017's dB) or "log10_cd_m2"; thresholds and threshold floors are in the same unit.
// Further stimulus dimensions are numeric columns of the condition table (`stimulus_columns`):
// the track shows the rows named in `conditions`, which must hold every combination of those
// columns' values exactly once, and QUEST+ picks the row with the intensity. Their grids
// (spec.stimulus[1..]) are filled from the rows when the procedure is built
// (quest_plus_track_grid in protocols/adaptive_procedure.h).
struct QuestPlusTrackSpec {
  QuestPlusSpec spec;
  std::string intensity_unit = "db_cd_m2";
  std::vector<std::string> stimulus_columns;
  std::vector<std::string> conditions;  // empty: the track's `condition` (or the first row)
};

struct AdaptiveTrackSpec {
  std::string condition;  // name of the condition row; empty: the first row
  StaircaseSpec staircase;  // used when procedure == "staircase"
  QuestSpec quest;          // used when procedure == "quest"
  QuestPlusTrackSpec quest_plus;  // used when procedure == "quest_plus" or "psi"
  SourceLocation where;
};

// How an answer moves a staircase ([procedure] response_rule; docs/PROCEDURES.md, "PSE
// staircases"):
// - correct: the answer is scored against the brighter source and the track converges on a
//   threshold of seeing the difference (n-up/m-down);
// - pse: the answer is an appearance judgement without a right answer (Spencer et al. 1995,
//   section 4: "Image A Brighter", "Image B Brighter", "Neither"): "comparison brighter" steps the
//   comparison down, "reference brighter" steps it up, "neither" turns the track around (it has
//   crossed into the band the observer cannot tell apart), so a 1-up/1-down track oscillates
//   around the point of subjective equality (PSE).
enum class AdaptiveResponseRule { correct, pse };
std::string to_string(AdaptiveResponseRule rule);

struct AdaptiveSpec {
  std::vector<AdaptiveTrackSpec> tracks;  // interleaved when more than one
  int threshold_reversals = 6;  // staircase threshold: mean of the last k reversal intensities
  AdaptiveResponseRule response_rule = AdaptiveResponseRule::correct;
  // [procedure] glare_on = "reference": the condition's glare is applied to the reference side only
  // and the comparison is shown without glare (Spencer 1995: the glare image against a plain
  // disc); "frame" (default): to the whole frame.
  bool glare_reference_only = false;
  // [procedure] glare_keeps_peak = true (with glare_on = "reference"): the glared reference is
  // scaled so that its brightest pixel is the reference scene's peak (stimuli/position_glare.h,
  // GlareLayer::keep_peak): Spencer's glare image peaks at 75 % of the display whatever its glare.
  bool glare_keeps_peak = false;
  // [procedure] tracks_per_condition = true: every track ([procedure] or each
  // [[procedure.staircases]] entry) runs once per condition row (expand_tracks_per_condition in
  // protocols/adaptive_config.h); false once expanded.
  bool tracks_per_condition = false;
  SourceLocation tracks_per_condition_where;
};

// Likert ratings (Luidolt 2020, section 7.2): every condition row's scene rated on every named
// category, 1..scale_points. A row's scene may be a physical object ("real:desk lamp",
// core/real_stimulus.h).
struct RatingSpec {
  std::vector<std::string> categories;
  int scale_points = 5;
  // What the ends of the scale mean, shown in the question: empty, or two texts, for 1 and for
  // scale_points (Luidolt 2020, 7.2.1: "completely different", "exactly the same").
  std::vector<std::string> scale_anchors;
  // How a category is named in the question when its own name does not read as one ("overall":
  // "Rate the overall similarity from 1 ..."); the trials and the analysis keep the category.
  std::map<std::string, std::string> category_labels;
  int repetitions = 1;
};

// Double adjustment (Yoshida et al. 2008, as used by Ritschel et al. 2009, section 6.1): the
// condition row's "target" scene centred between two copies of its "comparison" scene, whose
// luminances the observer adjusts simultaneously, in log steps, until they match the target.
struct AdjustmentSpec {
  double coarse_step_log10 = 0.1;   // one coarse key press: x 10^0.1 (about 26 %)
  double fine_step_log10 = 0.01;    // one fine key press: x 10^0.01 (about 2.3 %)
  // Start values: 10^(log10(target peak) + u), u uniform in [-range, range], drawn per trial and
  // spot (stream adjustment_start), so the starting point gives the answer away to nobody.
  double start_range_log10 = 0.3;
  int repetitions = 1;
};

struct SimulatedObserverSpec {
  // 2-AFC Weibull psychometric function of the |log10| luminance ratio of the two sources.
  double threshold_log10 = 0.05;
  double slope = 3.5;
  double lapse = 0.02;
  double response_time_median_s = 0.6;
  // Ratings: the simulated rating is round(mean + rating_sd * N(0, 1)) clamped to the scale; the
  // mean is the condition row's "simulated_rating" (the scale's middle when absent).
  double rating_sd = 0.7;
  // Adjustment: each setting is the target's peak times 10^(match_sd_log10 * N(0, 1)).
  double match_sd_log10 = 0.05;
  // Choices between two conditions without a right answer (protocols/observer_preferences.h).
  std::vector<ConditionPreference> preferences;
  // Appearance judgements of a PSE staircase (Spencer et al. 1995, section 4): a source shown
  // with glare gain g looks (1 + glare_brightening_per_gain g) times its luminance; the observer
  // compares the perceived log10 luminances of the two sides with Gaussian noise of SD
  // appearance_sd_log10 and answers "neither" when the noisy difference is within
  // +-neither_band_log10. The PSE of a source at L is then L (1 + k g) exactly.
  double glare_brightening_per_gain = 0.0;
  double appearance_sd_log10 = 0.03;
  double neither_band_log10 = 0.02;
  // Forced choice between two sides with a glare mode each (condition columns glare_a and glare_b):
  // a side shown in glare mode m looks (1 + glare_mode_brightening[m]) times its luminance (modes
  // not listed: 1). When the map is not empty such trials are answered as appearance judgements
  // (perceived log10 difference plus N(0, appearance_sd_log10^2) noise, the sign names the side),
  // so P(scene_b named) = Phi((log10(L_b / L_a) + log10((1 + b_b) / (1 + b_a))) / sd) and the
  // point of subjective equality lies exactly at L_b / L_a = (1 + b_a) / (1 + b_b).
  std::map<std::string, double> glare_mode_brightening;
};

struct Experiment {
  std::string source_file;  // absolute path of the TOML file (or "<stored config>")
  std::string name;
  std::string description;
  std::uint64_t seed = 1;
  DisplaySpec display;
  SourceLocation stereo_where;  // [display] stereo's value, for refusals that depend on the scenes
  SourceLocation stimulus_gap_where;  // [display] stimulus_gap_deg's value (or the table), likewise
  // [display] output: where the study is meant to be shown, "window" or "openxr" (a headset); empty
  // when the file does not say (a window). `run --display` wins over it.
  std::string display_output;
  SourceLocation display_output_where;
  // [display] engine (core/frame_engine_request.h): what makes the frames; `--engine` replaces it.
  FrameEngineRequest engine = FrameEngineRequest::automatic;
  std::map<std::string, SceneSpec> scenes;
  std::string procedure = "forced_choice";
  ForcedChoiceSpec forced_choice;
  AdaptiveSpec adaptive;  // staircase and quest
  RatingSpec rating;
  AdjustmentSpec adjustment;
  StraylightSpec straylight;  // procedure == "straylight": no scenes, conditions or blocks
  std::vector<ConditionRow> conditions;
  SimulatedObserverSpec simulated_observer;
  GlareSpec glare;  // [glare] and the default glare mode of conditions
  // [glare] straylight = "measured": where the key's value is. The session sets the observer eye's
  // straylight from the participant's most recent reliable measurement in its database before it
  // starts (runner/session/straylight_session.h), and stores the value it used.
  std::optional<SourceLocation> straylight_measured;
  // [perception]: the perception stages around the glare (every stage off by default) and the
  // default switches of conditions (column "perception").
  PerceptionSettings perception = perception_defaults();
  // [analysis]: the report's axis words and display names (protocols/analysis_config.h).
  AnalysisLabels analysis;
  // [observer.refraction], [spectacles.NAME] and [observer] spectacles: the observer's refraction
  // and the spectacles worn (default of the column "spectacles").
  ObserverOptics observer_optics;
  PresentationSpec presentation;  // [presentation]: screens, fixation, intervals, response window, feedback
  DesignSpec design;  // [[blocks]], their order and the participant number (protocols/block_design.h)
};

// Parses and validates a file. Throws ConfigError (file:line:column, key) for syntax errors,
// unknown keys, wrong types, out-of-range values, missing CSV files or columns, and conditions
// that name unknown scenes. Scene files are not opened here (see stimuli/scene_library.h).
Experiment load_experiment(const std::string& path);
// The same from text; relative paths resolve against base_dir.
Experiment parse_experiment_text(const std::string& toml_text, const std::string& origin_name,
                                 const std::string& base_dir);

// The fully resolved experiment as TOML (defaults explicit, absolute paths, conditions inline as
// [[conditions.rows]]). parse_experiment_text(resolved_config_toml(e), ...) gives back e.
std::string resolved_config_toml(const Experiment& experiment);

}  // namespace glarelab

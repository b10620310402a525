// The experiment as it will actually run, written back as TOML: every default explicit, every
// path absolute, the condition table inline. Stored with each session, it reproduces the session
// without the original files, and it reads back through the same strict parser.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <toml++/toml.h>

#include "protocols/block_config.h"
#include "protocols/experiment.h"
#include "protocols/generated_scene_config.h"
#include "protocols/scene_file_config.h"
#include "protocols/observer_optics_config.h"
#include "protocols/straylight_config.h"

namespace glarelab {
namespace {

// toml++ prints sub-tables in key order; printing each section from its own one-entry root
// keeps the order of the documentation (experiment, display, scenes, procedure, ...).
// A key as TOML text: bare when it can be ([A-Za-z0-9_-]+), else a basic string with escapes.
// Keys that come from the experiment's own names (scenes, condition columns) are printed with this,
// not by toml++: toml++ 3.3 prints a key holding a single quote, a tab or a newline bare, which
// does not read back (found by the experiment_file fuzz target: a column named g'are).
std::string toml_key(const std::string& key) {
  const bool bare = !key.empty() && std::all_of(key.begin(), key.end(), [](unsigned char c) {
    return std::isalnum(c) != 0 || c == '_' || c == '-';
  });
  if (bare) return key;
  std::string text = "\"";
  for (const unsigned char c : key) {
    switch (c) {
      case '"': text += "\\\""; break;
      case '\\': text += "\\\\"; break;
      case '\b': text += "\\b"; break;
      case '\t': text += "\\t"; break;
      case '\n': text += "\\n"; break;
      case '\f': text += "\\f"; break;
      case '\r': text += "\\r"; break;
      default:
        if (c < 0x20 || c == 0x7f) {
          char escaped[8];
          std::snprintf(escaped, sizeof escaped, "\\u%04X", c);
          text += escaped;
        } else {
          text += static_cast<char>(c);
        }
    }
  }
  return text + "\"";
}

void print_section(std::ostringstream& out, const std::string& name, toml::table section) {
  toml::table root;
  root.insert(name, std::move(section));
  out << root << "\n\n";
}

toml::array number_array(const std::vector<double>& values) {
  toml::array array;
  for (double v : values) array.push_back(v);
  return array;
}

// A QUEST+ / Psi track with every grid written out (defaults included), so the stored design
// rebuilds the same grids whatever the defaults of a later version.
toml::table quest_plus_track_table(const AdaptiveTrackSpec& track) {
  const QuestPlusTrackSpec& qp = track.quest_plus;
  const QuestPlusSpec& spec = qp.spec;
  toml::table table{{"name", spec.name},
                    {"function", to_string(spec.shape)},
                    {"intensity_unit", qp.intensity_unit},
                    {"intensities", number_array(spec.stimulus.front().values)},
                    {"guess_equals_lapse", spec.guess_equals_lapse},
                    {"max_trials", spec.max_trials}};
  toml::table coefficients, prior;
  for (const ParameterAxis& axis : spec.parameters) {
    if (axis.role == ParameterRole::threshold_coefficient) {
      coefficients.insert(qp.stimulus_columns.at(axis.stimulus_dimension - 1), number_array(axis.values));
    } else {
      table.insert(axis.name, number_array(axis.values));
    }
    if (!axis.prior.empty()) prior.insert(axis.name, number_array(axis.prior));
  }
  if (!qp.stimulus_columns.empty()) {
    toml::array columns;
    for (const std::string& column : qp.stimulus_columns) columns.push_back(column);
    table.insert("stimulus_columns", std::move(columns));
    table.insert("threshold_coefficients", std::move(coefficients));
  }
  if (!prior.empty()) table.insert("prior", std::move(prior));
  if (spec.stop_sd) {
    table.insert("stop_sd", *spec.stop_sd);
    table.insert("stop_sd_parameter", spec.stop_sd_parameter);
    table.insert("min_trials", spec.min_trials);
  }
  if (!qp.conditions.empty()) {
    toml::array conditions;
    for (const std::string& name : qp.conditions) conditions.push_back(name);
    table.insert("conditions", std::move(conditions));
  }
  if (!track.condition.empty()) table.insert("condition", track.condition);
  return table;
}

// Every parameter of one adaptive track, explicit.
toml::table adaptive_track_table(const Experiment& experiment, const AdaptiveTrackSpec& track) {
  if (experiment.procedure == "quest_plus" || experiment.procedure == "psi") return quest_plus_track_table(track);
  toml::table table;
  if (experiment.procedure == "staircase") {
    const StaircaseSpec& s = track.staircase;
    toml::array steps;
    for (double step : s.step_sizes) steps.push_back(step);
    table = toml::table{{"name", s.name},
                        {"start_intensity", s.start_value},
                        {"step_sizes", std::move(steps)},
                        {"step_type", to_string(s.step_type)},
                        {"n_up", s.n_up},
                        {"n_down", s.n_down},
                        {"n_reversals", s.n_reversals},
                        {"n_trials", s.n_trials},
                        {"apply_initial_rule", s.apply_initial_rule}};
    if (s.min_value) table.insert("min_value", *s.min_value);
    if (s.max_value) table.insert("max_value", *s.max_value);
  } else {
    const QuestSpec& q = track.quest;
    table = toml::table{{"name", q.name},         {"t_guess", q.t_guess}, {"t_guess_sd", q.t_guess_sd},
                        {"p_threshold", q.p_threshold}, {"beta", q.beta}, {"delta", q.delta},
                        {"gamma", q.gamma},       {"grain", q.grain},     {"range", q.range},
                        {"method", to_string(q.placement)}, {"n_trials", q.n_trials}};
    if (q.min_value) table.insert("min_value", *q.min_value);
    if (q.max_value) table.insert("max_value", *q.max_value);
  }
  if (!track.condition.empty()) table.insert("condition", track.condition);
  return table;
}

}  // namespace

namespace {
const char* display_encoding_name(DisplayEncoding encoding) {
  switch (encoding) {
    case DisplayEncoding::srgb: return "srgb";
    case DisplayEncoding::gamma: return "gamma";
    case DisplayEncoding::pq: return "pq";
    case DisplayEncoding::table: return "table";
  }
  return "srgb";
}

// [procedure] of a rating: anchors and labels only when given, so configurations stored before
// they existed read back unchanged.
toml::table rating_procedure_toml(const RatingSpec& rating) {
  toml::array categories;
  for (const std::string& category : rating.categories) categories.push_back(category);
  toml::table procedure{{"type", "rating"},
                        {"categories", std::move(categories)},
                        {"scale_points", rating.scale_points},
                        {"repetitions", rating.repetitions}};
  if (!rating.scale_anchors.empty()) {
    toml::array anchors;
    for (const std::string& anchor : rating.scale_anchors) anchors.push_back(anchor);
    procedure.insert("scale_anchors", std::move(anchors));
  }
  if (!rating.category_labels.empty()) {
    toml::table labels;
    for (const auto& [category, label] : rating.category_labels) labels.insert(category, label);
    procedure.insert("category_labels", std::move(labels));
  }
  return procedure;
}

}  // namespace

std::string resolved_config_toml(const Experiment& experiment) {
  if (experiment.seed > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
    // TOML integers are signed 64-bit; a larger seed could not be read back.
    throw std::out_of_range("seed " + std::to_string(experiment.seed) + " does not fit a TOML integer");
  }
  std::ostringstream out;
  out << "# Resolved experiment configuration (defaults explicit, paths absolute).\n\n";

  print_section(out, "experiment",
                toml::table{{"name", experiment.name},
                            {"description", experiment.description},
                            {"seed", static_cast<std::int64_t>(experiment.seed)}});

  const DisplaySpec& display = experiment.display;
  toml::table display_table{{"width_px", display.width_px},
                            {"height_px", display.height_px},
                            {"refresh_hz", display.refresh_hz},
                            {"viewing_distance_mm", display.viewing_distance_mm},
                            {"pixel_pitch_mm", display.pixel_pitch_mm},
                            {"peak_luminance_cd_m2", display.peak_luminance_cd_m2},
                            {"background_cd_m2", display.background_cd_m2},
                            {"encoding", display_encoding_name(display.encoding)},
                            {"gamma", display.gamma},
                            {"monitor", display.monitor},
                            {"fullscreen", display.fullscreen},
                            {"stimulus_gap_deg", display.stimulus_gap_deg}};
  // The encoding's own keys only with that encoding: elsewhere they are refused on reading.
  if (display.encoding == DisplayEncoding::pq)
    display_table.insert("primaries", display.primaries == DisplayPrimaries::bt2020 ? "bt2020" : "rec709");
  if (display.encoding == DisplayEncoding::table) display_table.insert("calibration", display.calibration.file);
  // Written only for stereo, so a mono experiment's resolved text is what it always was.
  if (display.stereo == StereoMode::side_by_side) display_table.insert("stereo", "side_by_side");
  if (display.bits_per_channel != 0) display_table.insert("bits_per_channel", display.bits_per_channel);
  if (!experiment.display_output.empty()) display_table.insert("output", experiment.display_output);
  // Written only when one was asked for, so that a resolved experiment without it reads as before.
  if (experiment.engine != FrameEngineRequest::automatic)
    display_table.insert("engine", std::string(spelling(experiment.engine)));
  print_section(out, "display", display_table);

  // A straylight measurement has no scenes (protocols/straylight_config.h).
  if (experiment.procedure != "straylight") out << "[scenes]\n";
  for (const auto& [name, scene] : experiment.scenes) {
    toml::table entry = scene.generated ? generated_scene_toml(*scene.generated)
                                        : scene_file_toml(scene);
    entry.is_inline(true);
    out << toml_key(name) << " = " << entry << "\n";
  }
  out << "\n";

  const ForcedChoiceSpec& spec = experiment.forced_choice;
  toml::array responses;
  for (const std::string& response : spec.responses) responses.push_back(response);
  toml::table procedure;
  if (experiment.procedure == "straylight") {
    procedure = straylight_procedure_toml(experiment.straylight);
  } else if (experiment.procedure == "rating") {
    procedure = rating_procedure_toml(experiment.rating);
  } else if (experiment.procedure == "adjustment") {
    const AdjustmentSpec& adjustment = experiment.adjustment;
    procedure = toml::table{{"type", experiment.procedure},
                            {"coarse_step_log10", adjustment.coarse_step_log10},
                            {"fine_step_log10", adjustment.fine_step_log10},
                            {"start_range_log10", adjustment.start_range_log10},
                            {"repetitions", adjustment.repetitions}};
  } else {
    procedure = toml::table{{"type", experiment.procedure},
                        {"alternatives", spec.alternatives},
                        {"layout", spec.layout},
                        {"question", spec.question},
                        {"responses", std::move(responses)}};
  }
  // The duration as the file gave it, so the rounding is redone (and logged) on resume. A
  // straylight presentation is its whole flicker cycles (`cycles`).
  const bool whole_cycles = experiment.procedure == "straylight";
  if (!whole_cycles && spec.stimulus_duration_s) {
    procedure.insert("stimulus_duration_s", *spec.stimulus_duration_s);
  } else if (!whole_cycles) {
    procedure.insert("stimulus_frames", spec.stimulus_frames);
  }
  if (experiment.procedure == "forced_choice") {
    procedure.insert("repetitions", spec.repetitions);
    procedure.insert("counterbalance_sides", spec.counterbalance_sides);
  } else if (experiment.procedure == "staircase" || experiment.procedure == "quest" ||
             experiment.procedure == "quest_plus" || experiment.procedure == "psi") {
    if (experiment.procedure == "staircase" || experiment.procedure == "quest")
      procedure.insert("threshold_reversals", experiment.adaptive.threshold_reversals);
    // Written only when not the default, so configurations stored before these keys read the same.
    if (experiment.adaptive.response_rule != AdaptiveResponseRule::correct)
      procedure.insert("response_rule", to_string(experiment.adaptive.response_rule));
    if (experiment.adaptive.glare_reference_only) procedure.insert("glare_on", "reference");
    if (experiment.adaptive.glare_keeps_peak) procedure.insert("glare_keeps_peak", true);
    toml::array tracks;
    for (const AdaptiveTrackSpec& track : experiment.adaptive.tracks) tracks.push_back(adaptive_track_table(experiment, track));
    procedure.insert("staircases", std::move(tracks));
  }
  insert_block_keys(experiment.design, procedure);
  print_section(out, "procedure", std::move(procedure));

  const SimulatedObserverSpec& observer = experiment.simulated_observer;
  toml::table simulated{{"threshold_log10", observer.threshold_log10},
                        {"slope", observer.slope},
                        {"lapse", observer.lapse},
                        {"response_time_median_s", observer.response_time_median_s},
                        {"rating_sd", observer.rating_sd},
                        {"match_sd_log10", observer.match_sd_log10},
                        {"glare_brightening_per_gain", observer.glare_brightening_per_gain},
                        {"appearance_sd_log10", observer.appearance_sd_log10},
                        {"neither_band_log10", observer.neither_band_log10}};
  if (!observer.preferences.empty()) simulated.insert("preferences", preferences_toml(observer.preferences));
  if (!observer.glare_mode_brightening.empty()) {
    toml::table brightening;
    for (const auto& [mode, value] : observer.glare_mode_brightening) brightening.insert(mode, value);
    simulated.insert("glare_mode_brightening", std::move(brightening));
  }
  const ObserverEye& eye = experiment.glare.observer_eye;
  toml::table observer_table{{"age_years", eye.age_years}, {"pigmentation", eye.pigmentation},
                             {"spectacles", experiment.observer_optics.spectacles_worn}, {"simulated", std::move(simulated)}};
  if (experiment.observer_optics.depth_of_field)
    observer_table.insert("depth_of_field", *experiment.observer_optics.depth_of_field);
  observer_table.insert("accommodation", std::string(spelling(experiment.observer_optics.accommodation)));
  if (experiment.observer_optics.refraction_stated)
    observer_table.insert("refraction", refraction_toml(experiment.observer_optics.refraction));
  print_section(out, "observer", std::move(observer_table));
  if (!experiment.observer_optics.spectacles.empty())
    print_section(out, "spectacles", spectacles_section_toml(experiment.observer_optics));
  print_section(out, "glare", glare_section_toml(experiment.glare));
  print_section(out, "perception", perception_section_toml(experiment.perception));
  print_section(out, "presentation", presentation_section_toml(experiment.presentation));
  if (!experiment.analysis.empty()) print_section(out, "analysis", analysis_section_toml(experiment.analysis));

  if (!experiment.design.blocks.empty()) {
    toml::table blocks;
    blocks.insert("blocks", blocks_toml(experiment.design));
    out << blocks << "\n\n";
  }

  // Rows are written key by key in column order (toml++ would sort the keys of a whole table);
  // values are formatted by toml++, keys by toml_key. The parser restores column order from the
  // keys' positions.
  for (const ConditionRow& row : experiment.conditions) {
    out << "[[conditions.rows]]\n";
    for (const auto& [column, value] : row.fields) out << toml_key(column) << " = " << toml::value<std::string>(value) << "\n";
    out << "\n";
  }
  return out.str();
}

}  // namespace glarelab

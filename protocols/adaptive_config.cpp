#include "protocols/adaptive_config.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>
#include <stdexcept>

#include "core/number_text.h"
#include "protocols/adaptive_procedure.h"
#include "protocols/quest_plus_config.h"

namespace glarelab {
namespace {

std::optional<int> read_count(TableReader& reader, std::string_view key, int minimum) {
  const std::optional<std::int64_t> value = reader.integer(key);
  if (!value) return std::nullopt;
  if (*value < minimum || *value > std::numeric_limits<int>::max())
    reader.fail(key, "must be >= " + number_text(minimum) + ", found " + number_text(*value));
  return static_cast<int>(*value);
}

std::vector<double> read_numbers(TableReader& reader, std::string_view key) {
  const toml::array* array = reader.array(key);
  std::vector<double> values;
  if (array == nullptr) return values;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& element = *array->get(i);
    if (const auto* f = element.as_floating_point()) {
      values.push_back(f->get());
    } else if (const auto* n = element.as_integer()) {
      values.push_back(static_cast<double>(n->get()));
    } else {
      throw ConfigError(to_location(element.source(), reader.file()),
                        reader.key_path(key) + "[" + std::to_string(i) + "]",
                        "expected a number, found " + describe_toml_type(element));
    }
  }
  if (values.empty()) reader.fail(key, "must list at least one step size");
  return values;
}

// Staircase keys of one table onto `spec` (keys absent keep the spec's values). Returns
// whether n_reversals was given, so a default can follow the length of the step list.
bool read_staircase_keys(TableReader& reader, StaircaseSpec& spec) {
  if (auto v = reader.number("start_intensity")) spec.start_value = *v;
  if (reader.node("step_sizes") != nullptr) spec.step_sizes = read_numbers(reader, "step_sizes");
  if (auto v = reader.string("step_type")) {
    try {
      spec.step_type = parse_step_type(*v);
    } catch (const std::invalid_argument&) {
      reader.fail("step_type", "unsupported step type '" + *v + "' (supported: 'db', 'log', 'lin')");
    }
  }
  if (auto v = read_count(reader, "n_up", 1)) spec.n_up = *v;
  if (auto v = read_count(reader, "n_down", 1)) spec.n_down = *v;
  if (auto v = read_count(reader, "n_trials", 0)) spec.n_trials = *v;
  const std::optional<int> reversals = read_count(reader, "n_reversals", 1);
  if (reversals) spec.n_reversals = *reversals;
  if (auto v = reader.number("min_value")) spec.min_value = *v;
  if (auto v = reader.number("max_value")) spec.max_value = *v;
  if (auto v = reader.boolean("apply_initial_rule")) spec.apply_initial_rule = *v;
  return reversals.has_value();
}

void read_quest_keys(TableReader& reader, QuestSpec& spec) {
  if (auto v = reader.number("t_guess")) spec.t_guess = *v;
  if (auto v = reader.number("t_guess_sd")) spec.t_guess_sd = *v;
  if (auto v = reader.number("p_threshold")) spec.p_threshold = *v;
  if (auto v = reader.number("beta")) spec.beta = *v;
  if (auto v = reader.number("delta")) spec.delta = *v;
  if (auto v = reader.number("gamma")) spec.gamma = *v;
  if (auto v = reader.number("grain")) spec.grain = *v;
  if (auto v = reader.number("range")) spec.range = *v;
  if (auto v = reader.string("method")) {
    try {
      spec.placement = parse_quest_placement(*v);
    } catch (const std::invalid_argument&) {
      reader.fail("method", "unsupported method '" + *v + "' (supported: 'quantile', 'mean', 'mode')");
    }
  }
  if (auto v = read_count(reader, "n_trials", 1)) spec.n_trials = *v;
  if (auto v = reader.number("min_value")) spec.min_value = *v;
  if (auto v = reader.number("max_value")) spec.max_value = *v;
}

// Reads one table's track keys onto `track` and validates the result; an invalid combination is
// reported at the first of the keys involved that the table itself sets.
// `defaults` is the [procedure] table when the track is an entry of [[procedure.staircases]]:
// a key it sets and the entry does not is reported there.
void read_track(TableReader& reader, TableReader* defaults, const std::string& procedure, AdaptiveTrackSpec& track,
                bool reversals_given) {
  if (auto v = reader.string("condition")) track.condition = *v;
  track.where = reader.table_location();
  try {
    if (procedure == "staircase") {
      reversals_given = read_staircase_keys(reader, track.staircase) || reversals_given;
      // Without an explicit count the staircase runs through its whole step list.
      if (!reversals_given)
        track.staircase.n_reversals = std::max(1, static_cast<int>(track.staircase.step_sizes.size()));
      validate_staircase_spec(track.staircase);
    } else {
      read_quest_keys(reader, track.quest);
      validate_quest_spec(track.quest);
    }
  } catch (const std::invalid_argument& error) {
    // Point at the key the message is about when this table sets it, else at the table.
    const std::string message = error.what();
    const std::vector<std::pair<std::string, std::string>> staircase_keys = {
        {"n_reversals", "n_reversals"}, {"step_sizes", "step_sizes"}, {"start_intensity", "start value"},
        {"min_value", "min_value"}};
    const std::vector<std::pair<std::string, std::string>> quest_keys = {
        {"t_guess_sd", "t_guess_sd"}, {"grain", "grain"},   {"range", "range"},
        {"beta", "beta"},             {"gamma", "gamma"},   {"delta", "delta"},
        {"p_threshold", "p_threshold"}, {"min_value", "min_value"}};
    for (const auto& [key, mentioned] : procedure == "staircase" ? staircase_keys : quest_keys) {
      if (message.find(mentioned) == std::string::npos) continue;
      if (reader.node(key) != nullptr) reader.fail(key, message);
      if (defaults != nullptr && defaults->node(key) != nullptr) defaults->fail(key, message);
    }
    reader.fail("", message);
  }
}

// glare_on, response_rule and tracks_per_condition: how the tracks show their rows and read the
// answers.
void read_track_layout_keys(TableReader& procedure, Experiment& experiment) {
  AdaptiveSpec& adaptive = experiment.adaptive;
  if (const std::optional<std::string> glare_on = procedure.string("glare_on")) {
    if (*glare_on == "reference") adaptive.glare_reference_only = true;
    else if (*glare_on != "frame")
      procedure.fail("glare_on", "unsupported value '" + *glare_on + "' (supported: 'frame', 'reference')");
  }
  if (const std::optional<bool> keep = procedure.boolean("glare_keeps_peak")) {
    if (*keep && !adaptive.glare_reference_only)
      procedure.fail("glare_keeps_peak", "keeps the glared reference's peak: needs glare_on = \"reference\"");
    adaptive.glare_keeps_peak = *keep;
  }
  const bool one_row_per_track = experiment.procedure == "staircase" || experiment.procedure == "quest";
  if (const std::optional<std::string> rule = procedure.string("response_rule")) {
    if (*rule == "pse") {
      if (experiment.procedure != "staircase")
        procedure.fail("response_rule", "response_rule = \"pse\" is a staircase's rule (type = \"staircase\")");
      adaptive.response_rule = AdaptiveResponseRule::pse;
    } else if (*rule != "correct") {
      procedure.fail("response_rule", "unsupported rule '" + *rule + "' (supported: 'correct', 'pse')");
    }
  }
  if (const std::optional<bool> per_condition = procedure.boolean("tracks_per_condition")) {
    if (*per_condition && !one_row_per_track)
      procedure.fail("tracks_per_condition", "for staircase and quest; QUEST+ tracks choose their rows themselves");
    adaptive.tracks_per_condition = *per_condition;
    adaptive.tracks_per_condition_where = procedure.value_location("tracks_per_condition");
  }
}

// The PSE rule turns the track at "neither" and steps on every answer: only 1-up/1-down
// converges on equality (n-down > 1 would converge on the point where the comparison is called
// brighter on 70.7 % of the answers naming a side). The track's range must be bounded: the first
// "neither" steps toward the middle of [min_value, max_value].
void check_pse_track(TableReader& reader, TableReader* defaults, const StaircaseSpec& spec) {
  const auto fail = [&](std::string_view key, const std::string& message) {
    if (reader.node(key) != nullptr) reader.fail(key, message);
    if (defaults != nullptr && defaults->node(key) != nullptr) defaults->fail(key, message);
    reader.fail(key, message);
  };
  if (spec.n_up != 1) fail("n_up", "response_rule = \"pse\" needs n_up = 1 (1-up/1-down converges on equality)");
  if (spec.n_down != 1) fail("n_down", "response_rule = \"pse\" needs n_down = 1 (1-up/1-down converges on equality)");
  if (!spec.min_value) fail("min_value", "response_rule = \"pse\" needs min_value (the comparison's range, e.g. 0 cd/m2)");
  if (!spec.max_value)
    fail("max_value", "response_rule = \"pse\" needs max_value (the comparison's range, e.g. the display's peak)");
  if (spec.start_value < *spec.min_value || spec.start_value > *spec.max_value)
    fail("start_intensity", "must lie in [min_value, max_value]");
}

}  // namespace

std::string to_string(AdaptiveResponseRule rule) { return rule == AdaptiveResponseRule::pse ? "pse" : "correct"; }

void read_adaptive_procedure(TableReader& procedure, Experiment& experiment) {
  AdaptiveSpec& adaptive = experiment.adaptive;
  read_track_layout_keys(procedure, experiment);
  if (experiment.procedure == "quest_plus" || experiment.procedure == "psi") {
    read_quest_plus_tracks(procedure, experiment);
    return;
  }
  if (auto v = read_count(procedure, "threshold_reversals", 1)) adaptive.threshold_reversals = *v;
  const bool staircase = experiment.procedure == "staircase";
  AdaptiveTrackSpec defaults;
  // QUEST's guess rate is one over the number of alternatives unless the file says otherwise.
  defaults.quest.gamma = 1.0 / experiment.forced_choice.alternatives;
  defaults.staircase.name = defaults.quest.name = staircase ? "staircase" : "quest";
  bool reversals_given = false;
  if (auto v = procedure.string("condition")) defaults.condition = *v;
  if (staircase) {
    reversals_given = read_staircase_keys(procedure, defaults.staircase);
  } else {
    read_quest_keys(procedure, defaults.quest);
  }

  const toml::array* tracks = procedure.array("staircases");
  if (tracks == nullptr) {
    AdaptiveTrackSpec track = defaults;
    read_track(procedure, nullptr, experiment.procedure, track, reversals_given);
    if (adaptive.response_rule == AdaptiveResponseRule::pse) check_pse_track(procedure, nullptr, track.staircase);
    if (adaptive.tracks_per_condition && !track.condition.empty())
      procedure.fail("condition", "tracks_per_condition runs the track for every condition row; remove condition");
    adaptive.tracks.push_back(std::move(track));
    return;
  }
  if (tracks->empty()) procedure.fail("staircases", "at least one [[procedure.staircases]] entry is required");
  for (std::size_t i = 0; i < tracks->size(); ++i) {
    const toml::node& element = *tracks->get(i);
    const std::string key = procedure.key_path("staircases") + "[" + std::to_string(i) + "]";
    if (!element.is_table())
      throw ConfigError(to_location(element.source(), procedure.file()), key,
                        "expected a table with a name and staircase parameters, found " + describe_toml_type(element));
    TableReader reader(*element.as_table(), key, procedure.file());
    AdaptiveTrackSpec track = defaults;
    const std::optional<std::string> name = reader.string("name");
    if (!name || name->empty()) reader.fail("name", "each interleaved staircase needs a non-empty name");
    for (const AdaptiveTrackSpec& other : adaptive.tracks)
      if (other.staircase.name == *name) reader.fail("name", "duplicate staircase name '" + *name + "'");
    track.staircase.name = track.quest.name = *name;
    read_track(reader, &procedure, experiment.procedure, track, reversals_given);
    if (adaptive.response_rule == AdaptiveResponseRule::pse) check_pse_track(reader, &procedure, track.staircase);
    if (adaptive.tracks_per_condition && !track.condition.empty()) {
      if (reader.node("condition") != nullptr)
        reader.fail("condition", "tracks_per_condition runs every track for every condition row; remove condition");
      procedure.fail("condition", "tracks_per_condition runs every track for every condition row; remove condition");
    }
    reader.report_unused();
    adaptive.tracks.push_back(std::move(track));
  }
}

void expand_tracks_per_condition(Experiment& experiment) {
  AdaptiveSpec& adaptive = experiment.adaptive;
  if (!adaptive.tracks_per_condition) return;
  std::vector<AdaptiveTrackSpec> expanded;
  const bool several = adaptive.tracks.size() > 1;
  for (const ConditionRow& row : experiment.conditions) {
    for (const AdaptiveTrackSpec& track : adaptive.tracks) {
      AdaptiveTrackSpec copy = track;
      copy.condition = row.name();
      const std::string name = several ? row.name() + "/" + track.staircase.name : row.name();
      copy.staircase.name = copy.quest.name = name;
      for (const AdaptiveTrackSpec& other : expanded)
        if (other.staircase.name == name)
          throw ConfigError(row.where, "name", "tracks_per_condition: two tracks would be named '" + name + "'");
      expanded.push_back(std::move(copy));
    }
  }
  adaptive.tracks = std::move(expanded);
  adaptive.tracks_per_condition = false;
}

void check_adaptive_conditions(const Experiment& experiment) {
  if (experiment.procedure == "quest_plus" || experiment.procedure == "psi") {
    for (const AdaptiveTrackSpec& track : experiment.adaptive.tracks) {
      try {
        (void)quest_plus_track_grid(experiment, track);
      } catch (const std::invalid_argument& error) {
        throw ConfigError(track.where, track.quest_plus.conditions.empty() ? "condition" : "conditions", error.what());
      }
    }
    return;
  }
  for (const AdaptiveTrackSpec& track : experiment.adaptive.tracks) {
    if (track.condition.empty()) continue;
    bool found = false;
    for (const ConditionRow& row : experiment.conditions) found = found || row.name() == track.condition;
    if (!found)
      throw ConfigError(track.where, "condition", "no condition row named '" + track.condition + "'");
  }
}

}  // namespace glarelab

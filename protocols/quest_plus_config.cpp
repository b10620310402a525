#include "protocols/quest_plus_config.h"

#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/number_text.h"
#include "protocols/adaptive_procedure.h"

namespace glarelab {
namespace {

std::optional<int> read_count(TableReader& reader, std::string_view key, int minimum) {
  const std::optional<std::int64_t> value = reader.integer(key);
  if (!value) return std::nullopt;
  if (*value < minimum || *value > std::numeric_limits<int>::max())
    reader.fail(key, "must be >= " + number_text(minimum) + ", found " + number_text(*value));
  return static_cast<int>(*value);
}

// At most this many values in one grid: beyond it the posterior would not fit memory anyway.
constexpr std::size_t kMaxGridValues = 100000;

// One number of an array, at its own location.
double array_number(const TableReader& reader, const std::string& key, const toml::node& element) {
  if (const auto* f = element.as_floating_point()) {
    if (!std::isfinite(f->get())) throw ConfigError(to_location(element.source(), reader.file()), key, "must be finite");
    return f->get();
  }
  if (const auto* n = element.as_integer()) return static_cast<double>(n->get());
  throw ConfigError(to_location(element.source(), reader.file()), key,
                    "expected a number, found " + describe_toml_type(element));
}

std::vector<double> numbers_of(const TableReader& reader, const std::string& key, const toml::array& array) {
  std::vector<double> values;
  for (std::size_t i = 0; i < array.size(); ++i)
    values.push_back(array_number(reader, key + "[" + std::to_string(i) + "]", *array.get(i)));
  return values;
}

// A grid: one number (a fixed value), an array of numbers, or an inline table
// { from = A, to = B, step = S } for A, A + S, A + 2 S, ... up to B (inclusive, within 1e-9 S).
std::optional<std::vector<double>> read_grid(TableReader& reader, std::string_view key) {
  const toml::node* node = reader.node(key);
  if (node == nullptr) return std::nullopt;
  std::vector<double> values;
  if (node->is_number()) {
    values.push_back(*reader.number(key));
  } else if (const toml::array* array = node->as_array()) {
    values = numbers_of(reader, reader.key_path(key), *array);
    if (values.empty()) reader.fail(key, "must list at least one value");
  } else if (const toml::table* table = node->as_table()) {
    TableReader range(*table, reader.key_path(key), reader.file());
    const std::optional<double> from = range.number("from"), to = range.number("to"), step = range.number("step");
    range.report_unused();
    if (!from || !to || !step) reader.fail(key, "a grid table needs from, to and step");
    if (!(*step > 0.0)) range.fail("step", "must be > 0");
    if (*to < *from) range.fail("to", "must be >= from");
    const double count = std::floor((*to - *from) / *step + 1e-9) + 1.0;
    if (!(count <= static_cast<double>(kMaxGridValues)))
      reader.fail(key, "more than " + number_text(static_cast<std::int64_t>(kMaxGridValues)) + " grid values");
    for (int i = 0; i < static_cast<int>(count); ++i) values.push_back(*from + i * *step);
  } else {
    reader.fail(key, "expected a number, an array of numbers or { from, to, step }, found " + describe_toml_type(*node));
  }
  if (values.size() > kMaxGridValues)
    reader.fail(key, "more than " + number_text(static_cast<std::int64_t>(kMaxGridValues)) + " grid values");
  return values;
}

// The QUEST+ keys one table sets; a track's keys overlay those of [procedure].
struct QuestPlusKeys {
  std::optional<std::string> function, intensity_unit, stop_sd_parameter;
  std::optional<std::vector<double>> intensities, threshold, slope, sd, guess, lapse, threshold_floor;
  std::optional<std::vector<std::string>> stimulus_columns, conditions;
  std::optional<std::map<std::string, std::vector<double>>> coefficients, prior;
  std::optional<bool> guess_equals_lapse;
  std::optional<int> max_trials, min_trials;
  std::optional<double> stop_sd;
};

std::vector<std::string> string_list(TableReader& reader, std::string_view key, const std::string& what) {
  const std::optional<std::vector<ArrayString>> given = reader.distinct_names(key, what);
  std::vector<std::string> names;
  if (given)
    for (const ArrayString& name : *given) names.push_back(name.value);
  return names;
}

// A table of grids or weights named by the user (parameter or column names).
std::map<std::string, std::vector<double>> read_named_grids(TableReader& reader, std::string_view key, bool weights) {
  const toml::table* table = reader.table(key);
  std::map<std::string, std::vector<double>> grids;
  TableReader inner(*table, reader.key_path(key), reader.file());
  for (const auto& [name, node] : *table) {
    const std::string name_text(name.str());
    if (weights) {
      const toml::array* array = node.as_array();
      if (array == nullptr) inner.fail(name_text, "expected an array of weights, one per grid value");
      grids[name_text] = numbers_of(inner, inner.key_path(name_text), *array);
    } else {
      grids[name_text] = *read_grid(inner, name_text);
    }
  }
  inner.consume_all();
  return grids;
}

void read_quest_plus_keys(TableReader& reader, QuestPlusKeys& keys) {
  if (auto v = reader.string("function")) keys.function = *v;
  if (auto v = reader.string("intensity_unit")) keys.intensity_unit = *v;
  if (auto v = read_grid(reader, "intensities")) keys.intensities = *v;
  if (auto v = read_grid(reader, "threshold")) keys.threshold = *v;
  if (auto v = read_grid(reader, "threshold_floor")) keys.threshold_floor = *v;
  if (auto v = read_grid(reader, "slope")) keys.slope = *v;
  if (auto v = read_grid(reader, "sd")) keys.sd = *v;
  if (auto v = read_grid(reader, "guess")) keys.guess = *v;
  if (auto v = read_grid(reader, "lapse")) keys.lapse = *v;
  if (auto v = reader.boolean("guess_equals_lapse")) keys.guess_equals_lapse = *v;
  if (reader.node("stimulus_columns") != nullptr) keys.stimulus_columns = string_list(reader, "stimulus_columns", "stimulus column");
  if (reader.node("conditions") != nullptr) keys.conditions = string_list(reader, "conditions", "condition");
  if (reader.node("threshold_coefficients") != nullptr)
    keys.coefficients = read_named_grids(reader, "threshold_coefficients", false);
  if (reader.node("prior") != nullptr) keys.prior = read_named_grids(reader, "prior", true);
  if (auto v = read_count(reader, "max_trials", 1)) keys.max_trials = *v;
  if (auto v = read_count(reader, "min_trials", 0)) keys.min_trials = *v;
  if (auto v = reader.number("stop_sd")) keys.stop_sd = *v;
  if (auto v = reader.string("stop_sd_parameter")) keys.stop_sd_parameter = *v;
}

template <typename T>
void overlay(std::optional<T>& base, const std::optional<T>& top) {
  if (top) base = top;
}

QuestPlusKeys overlay_keys(QuestPlusKeys base, const QuestPlusKeys& top) {
  overlay(base.function, top.function);
  overlay(base.intensity_unit, top.intensity_unit);
  overlay(base.stop_sd_parameter, top.stop_sd_parameter);
  overlay(base.intensities, top.intensities);
  overlay(base.threshold, top.threshold);
  overlay(base.slope, top.slope);
  overlay(base.sd, top.sd);
  overlay(base.guess, top.guess);
  overlay(base.lapse, top.lapse);
  overlay(base.threshold_floor, top.threshold_floor);
  overlay(base.stimulus_columns, top.stimulus_columns);
  overlay(base.conditions, top.conditions);
  overlay(base.coefficients, top.coefficients);
  overlay(base.prior, top.prior);
  overlay(base.guess_equals_lapse, top.guess_equals_lapse);
  overlay(base.max_trials, top.max_trials);
  overlay(base.min_trials, top.min_trials);
  overlay(base.stop_sd, top.stop_sd);
  return base;
}

// The track's QuestPlusTrackSpec from its keys (std::invalid_argument naming the key at fault).
// Psi (Kontsevich & Tyler 1999) differs only in its defaults (make_psi_spec: Palamedes'
// PAL_AMPM_setupPM) and in having one stimulus dimension.
QuestPlusTrackSpec assemble_quest_plus(const QuestPlusKeys& keys, const Experiment& experiment, const std::string& name) {
  const bool psi = experiment.procedure == "psi";
  QuestPlusTrackSpec track;
  QuestPlusSpec& spec = track.spec;
  spec.name = name;
  if (psi && (keys.stimulus_columns || keys.coefficients || keys.threshold_floor))
    throw std::invalid_argument(
        "psi has one stimulus dimension (intensity x threshold x slope): stimulus_columns, threshold_coefficients and "
        "threshold_floor need type = \"quest_plus\"");
  spec.shape = parse_psychometric_shape(keys.function.value_or("weibull"));
  track.intensity_unit = keys.intensity_unit.value_or(psi ? "log10_cd_m2" : "db_cd_m2");
  if (track.intensity_unit == "db_cd_m2") {
    spec.scale = StimulusScale::db;
  } else if (track.intensity_unit == "log10_cd_m2") {
    spec.scale = StimulusScale::log10;
  } else {
    throw std::invalid_argument("unsupported intensity_unit '" + track.intensity_unit +
                                "' (supported: 'db_cd_m2' = 20 log10 cd/m2, 'log10_cd_m2')");
  }
  if (!keys.intensities) throw std::invalid_argument("intensities: missing required grid of comparison intensities");
  spec.stimulus.push_back({"intensity", *keys.intensities});
  track.stimulus_columns = keys.stimulus_columns.value_or(std::vector<std::string>{});
  track.conditions = keys.conditions.value_or(std::vector<std::string>{});
  // Further stimulus dimensions: grids filled from the condition rows (quest_plus_track_grid).
  for (const std::string& column : track.stimulus_columns) spec.stimulus.push_back({column, {0.0}});

  auto add = [&](const std::string& axis_name, ParameterRole role, std::vector<double> values, std::size_t dimension = 0) {
    ParameterAxis a;
    a.name = axis_name;
    a.role = role;
    a.values = std::move(values);
    a.stimulus_dimension = dimension;
    spec.parameters.push_back(std::move(a));
  };
  // The order of questplus's csf example: floor, threshold, coefficients, slope, guess, lapse.
  if (keys.threshold_floor) add("threshold_floor", ParameterRole::threshold_floor, *keys.threshold_floor);
  add("threshold", ParameterRole::threshold, keys.threshold.value_or(*keys.intensities));
  if (keys.coefficients) {
    for (const auto& [column, grid] : *keys.coefficients) {
      const auto at = std::find(track.stimulus_columns.begin(), track.stimulus_columns.end(), column);
      if (at == track.stimulus_columns.end())
        throw std::invalid_argument("threshold_coefficients: '" + column + "' is not one of stimulus_columns");
      (void)grid;
    }
  }
  for (std::size_t i = 0; i < track.stimulus_columns.size(); ++i) {
    const std::string& column = track.stimulus_columns[i];
    if (!keys.coefficients || keys.coefficients->count(column) == 0)
      throw std::invalid_argument("threshold_coefficients: stimulus column '" + column +
                                  "' needs a grid of threshold change per unit of it");
    add("threshold_per_" + column, ParameterRole::threshold_coefficient, keys.coefficients->at(column), i + 1);
  }
  if (spec.shape == PsychometricShape::normal) {
    if (keys.slope) throw std::invalid_argument("slope: the normal function takes sd (its SD, in intensity units)");
    if (!keys.sd) throw std::invalid_argument("sd: missing; the normal function needs a grid of SDs in intensity units");
    add("sd", ParameterRole::sd, *keys.sd);
  } else {
    if (keys.sd) throw std::invalid_argument("sd: only the normal function takes sd; weibull and logistic take slope");
    if (!keys.slope && spec.shape == PsychometricShape::logistic)
      throw std::invalid_argument("slope: missing; the logistic function needs a slope grid (per intensity unit)");
    // Weibull: Watson 2017's beta = 3.5 (Examples 1, 4), Psi: Palamedes' 10^(-1 : 0.05 : 1).
    add("slope", ParameterRole::slope, keys.slope.value_or(psi ? psi_default_slopes() : std::vector<double>{3.5}));
  }
  spec.guess_equals_lapse = keys.guess_equals_lapse.value_or(false);
  if (spec.guess_equals_lapse && keys.guess) throw std::invalid_argument("guess: guess_equals_lapse sets the guess rate");
  if (!spec.guess_equals_lapse)
    add("guess", ParameterRole::guess, keys.guess.value_or(std::vector<double>{1.0 / experiment.forced_choice.alternatives}));
  add("lapse", ParameterRole::lapse, keys.lapse.value_or(std::vector<double>{0.02}));
  if (keys.prior) {
    for (const auto& prior_entry : *keys.prior) {
      // Named references, not a structured binding: the lambda uses the name, and capturing a
      // structured binding is C++20 that clang accepts only from version 16 (the fuzz build).
      const std::string& axis_name = prior_entry.first;
      const auto& weights = prior_entry.second;
      auto at = std::find_if(spec.parameters.begin(), spec.parameters.end(),
                             [&](const ParameterAxis& a) { return a.name == axis_name; });
      if (at == spec.parameters.end()) {
        std::string names;
        for (const ParameterAxis& a : spec.parameters) names += (names.empty() ? "" : ", ") + a.name;
        throw std::invalid_argument("prior: no parameter named '" + axis_name + "' (parameters: " + names + ")");
      }
      if (weights.size() != at->values.size())
        throw std::invalid_argument("prior: '" + axis_name + "' has " + std::to_string(weights.size()) +
                                    " weights for " + std::to_string(at->values.size()) + " grid values");
      at->prior = weights;
    }
  }
  spec.max_trials = keys.max_trials.value_or(psi ? 50 : 40);
  spec.min_trials = keys.min_trials.value_or(0);
  spec.stop_sd = keys.stop_sd;
  spec.stop_sd_parameter = keys.stop_sd_parameter.value_or("threshold");
  if (keys.min_trials && !keys.stop_sd) throw std::invalid_argument("min_trials: only meaningful with stop_sd");
  if (track.stimulus_columns.empty() && track.conditions.size() > 1)
    throw std::invalid_argument("conditions: several rows need stimulus_columns for QUEST+ to choose between them");
  validate_quest_plus_spec(spec);
  return track;
}

// The config key a QUEST+ message is about (the first whose name it mentions), else "".
std::string quest_plus_key_of(const std::string& message) {
  static const std::vector<std::pair<std::string, std::string>> keys = {
      {"threshold_coefficients", "threshold_coefficients"}, {"threshold_floor", "threshold_floor"},
      {"stimulus_columns", "stimulus_columns"}, {"intensity_unit", "intensity_unit"},
      {"intensities", "intensities"}, {"stimulus dimension 'intensity'", "intensities"},
      {"stop_sd", "stop_sd"}, {"min_trials", "min_trials"}, {"max_trials", "max_trials"},
      {"prior", "prior"}, {"guess + lapse", "lapse"}, {"guess_equals_lapse", "guess_equals_lapse"},
      {"'threshold'", "threshold"}, {"'slope'", "slope"}, {"slope:", "slope"}, {"'sd'", "sd"}, {"sd:", "sd"},
      {"'guess'", "guess"}, {"guess:", "guess"}, {"'lapse'", "lapse"}, {"function", "function"},
      {"conditions", "conditions"}, {"Weibull on a linear", "threshold"}};
  for (const auto& [mentioned, key] : keys)
    if (message.find(mentioned) != std::string::npos) return key;
  return "";
}

}  // namespace

void read_quest_plus_tracks(TableReader& procedure, Experiment& experiment) {
  QuestPlusKeys defaults;
  read_quest_plus_keys(procedure, defaults);
  const std::string default_name = experiment.procedure;
  std::optional<std::string> default_condition = procedure.string("condition");

  auto build = [&](TableReader* track_table, const QuestPlusKeys& keys, const std::string& name) {
    AdaptiveTrackSpec track;
    track.staircase.name = track.quest.name = name;
    track.condition = default_condition.value_or("");
    TableReader& reader = track_table != nullptr ? *track_table : procedure;
    const std::optional<std::string> own_condition =
        track_table != nullptr ? track_table->string("condition") : std::nullopt;
    if (own_condition) track.condition = *own_condition;
    track.where = reader.table_location();
    try {
      track.quest_plus = assemble_quest_plus(keys, experiment, name);
    } catch (const std::invalid_argument& error) {
      const std::string message = error.what();
      const std::string key = quest_plus_key_of(message);
      if (!key.empty() && reader.node(key) != nullptr) reader.fail(key, message);
      if (!key.empty() && procedure.node(key) != nullptr) procedure.fail(key, message);
      reader.fail("", message);
    }
    if (!track.quest_plus.conditions.empty() && !track.condition.empty())
      reader.fail("conditions", "give either condition or conditions");
    return track;
  };

  const toml::array* tracks = procedure.array("staircases");
  if (tracks == nullptr) {
    experiment.adaptive.tracks.push_back(build(nullptr, defaults, default_name));
    return;
  }
  if (tracks->empty()) procedure.fail("staircases", "at least one [[procedure.staircases]] entry is required");
  for (std::size_t i = 0; i < tracks->size(); ++i) {
    const toml::node& element = *tracks->get(i);
    const std::string key = procedure.key_path("staircases") + "[" + std::to_string(i) + "]";
    if (!element.is_table())
      throw ConfigError(to_location(element.source(), procedure.file()), key,
                        "expected a table with a name and QUEST+ parameters, found " + describe_toml_type(element));
    TableReader reader(*element.as_table(), key, procedure.file());
    const std::optional<std::string> name = reader.string("name");
    if (!name || name->empty()) reader.fail("name", "each interleaved track needs a non-empty name");
    for (const AdaptiveTrackSpec& other : experiment.adaptive.tracks)
      if (other.staircase.name == *name) reader.fail("name", "duplicate track name '" + *name + "'");
    QuestPlusKeys own;
    read_quest_plus_keys(reader, own);
    experiment.adaptive.tracks.push_back(build(&reader, overlay_keys(defaults, own), *name));
    reader.report_unused();
  }
}

}  // namespace glarelab

#include "protocols/observer_preferences.h"

#include <set>

#include "core/number_text.h"
#include "protocols/experiment.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {

std::vector<ConditionPreference> read_preferences(TableReader& simulated) {
  std::vector<ConditionPreference> preferences;
  const toml::table* table = simulated.table("preferences");
  if (table == nullptr) return preferences;
  TableReader reader(*table, simulated.key_path("preferences"), simulated.file());
  reader.consume_all();  // the keys are condition pairs chosen by the experimenter
  for (const auto& [key, node] : *table) {
    const std::string text(key.str());
    const std::size_t mark = text.find('>');
    ConditionPreference preference;
    preference.where = to_location(key.source(), simulated.file());
    if (mark == std::string::npos || text.find('>', mark + 1) != std::string::npos || mark == 0 ||
        mark + 1 == text.size())
      reader.fail_at_key(text, "expected a key \"PREFERRED>OTHER\" naming two conditions, e.g. \"dynamic>static\"");
    preference.preferred = text.substr(0, mark);
    preference.other = text.substr(mark + 1);
    if (preference.preferred == preference.other)
      reader.fail_at_key(text, "a condition cannot be preferred to itself");
    const std::optional<double> p = reader.number(text);
    if (!(*p >= 0.0 && *p <= 1.0)) reader.fail(text, "must be a probability in [0, 1], found " + number_text(*p));
    preference.probability = *p;
    for (const ConditionPreference& earlier : preferences) {
      const bool same = earlier.preferred == preference.preferred && earlier.other == preference.other;
      const bool reverse = earlier.preferred == preference.other && earlier.other == preference.preferred;
      if (same || reverse)
        reader.fail_at_key(text, "the pair '" + preference.preferred + "', '" + preference.other +
                                     "' already has a preference (\"" + earlier.preferred + ">" + earlier.other +
                                     "\"); give each pair once");
    }
    preferences.push_back(std::move(preference));
  }
  return preferences;
}

toml::table preferences_toml(const std::vector<ConditionPreference>& preferences) {
  toml::table table;
  for (const ConditionPreference& preference : preferences)
    table.insert(preference.preferred + ">" + preference.other, preference.probability);
  return table;
}

std::optional<double> preference_probability(const std::vector<ConditionPreference>& preferences,
                                             const std::string& first, const std::string& second) {
  for (const ConditionPreference& preference : preferences) {
    if (preference.preferred == first && preference.other == second) return preference.probability;
    if (preference.preferred == second && preference.other == first) return 1.0 - preference.probability;
  }
  return std::nullopt;
}

void check_preferences(const Experiment& experiment) {
  const std::vector<ConditionPreference>& preferences = experiment.simulated_observer.preferences;
  if (preferences.empty()) return;
  std::set<std::string> shown;
  for (const ConditionRow& row : experiment.conditions) {
    for (const char* column : {"condition_a", "condition_b"})
      if (const std::string* name = row.find(column)) shown.insert(*name);
  }
  for (const ConditionPreference& preference : preferences) {
    for (const std::string* name : {&preference.preferred, &preference.other}) {
      if (shown.count(*name) == 0)
        throw ConfigError(preference.where, "observer.simulated.preferences",
                          "no condition row shows '" + *name +
                              "' (preferences name the conditions of the condition_a and condition_b columns)");
    }
  }
}

}  // namespace glarelab

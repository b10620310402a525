#pragma once
// Preferences of the simulated observer between two conditions ([observer.simulated.preferences]):
// `"dynamic>static" = 0.75` makes it choose the side showing "dynamic" over the side showing
// "static" in 75 % of the trials that compare them and have no right answer (Ritschel et al. 2009,
// 6.1: which image is more attractive, more realistic -- or brighter, when both show the same
// scene at the same luminance and differ only in their glare). Condition names are those of the
// forced-choice rows' condition_a / condition_b columns.
#include <optional>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "core/errors.h"

namespace glarelab {

class TableReader;
struct Experiment;

struct ConditionPreference {
  std::string preferred;     // A of "A>B"
  std::string other;         // B of "A>B"
  double probability = 0.5;  // of choosing A when A and B are compared
  SourceLocation where;
};

// The [observer.simulated.preferences] table (`simulated` reads [observer.simulated]).
std::vector<ConditionPreference> read_preferences(TableReader& simulated);
// The table resolved_config_toml writes; empty when there are no preferences.
toml::table preferences_toml(const std::vector<ConditionPreference>& preferences);
// Probability of choosing `first` over `second`: p for "first>second", 1 - p for "second>first",
// nothing without an entry.
std::optional<double> preference_probability(const std::vector<ConditionPreference>& preferences,
                                             const std::string& first, const std::string& second);
// Every name must be a condition some forced-choice row shows (column condition_a or
// condition_b); otherwise a misspelt name would silently never apply. Throws ConfigError.
void check_preferences(const Experiment& experiment);

}  // namespace glarelab

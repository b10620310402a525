#include "analysis/forced_choice_analysis.h"

#include <algorithm>
#include <map>
#include <set>

namespace glarelab::analysis {
namespace {

// Positions of the two alternatives: side by side, or the two intervals of sequential 2-AFC.
const std::vector<std::string> kPositions = {"left", "right", "first", "second"};

// What stands at a position: its glare mode when the trial compares glare modes ("left_glare" =
// "dynamic": Ritschel et al. 2009, section 6.1, the same scene under two glare conditions),
// otherwise the scene shown there.
const std::string* option_at(const LoadedTrial& trial, const std::string& position) {
  if (const std::string* glare = trial.condition_value(position + "_glare")) return glare;
  return trial.condition_value(position);
}

struct Counts {
  std::map<std::string, long> chosen;
  long neither = 0;
};

using PairKey = std::pair<std::string, std::string>;  // sorted option names

std::string group_of(const LoadedTrial& trial, std::string& pool) {
  const std::string* scene = trial.condition_value("scene");
  const std::string* instruction = trial.condition_value("instruction");
  if (scene != nullptr || instruction != nullptr) {
    pool = instruction != nullptr ? "instruction=" + *instruction : "all scenes";
    std::string group;
    if (scene != nullptr) group = "scene=" + *scene;
    if (instruction != nullptr) group += (group.empty() ? "" : ", ") + std::string("instruction=") + *instruction;
    return group;
  }
  pool = "all conditions";
  if (const std::string* name = trial.condition_value("name")) return *name;
  std::string rest;
  for (const auto& [key, value] : trial.condition) {
    if (std::find(kPositions.begin(), kPositions.end(), key) != kPositions.end() || key.ends_with("_glare")) continue;
    rest += (rest.empty() ? "" : ", ") + key + "=" + value;
  }
  return rest.empty() ? "(no condition)" : rest;
}

PairPreference make_preference(const std::string& group, const PairKey& pair, const Counts& counts) {
  PairPreference preference;
  preference.group = group;
  const auto count = [&](const std::string& option) {
    const auto found = counts.chosen.find(option);
    return found == counts.chosen.end() ? 0L : found->second;
  };
  const long first = count(pair.first);
  const long second = count(pair.second);
  const bool first_leads = first >= second;
  preference.option_a = first_leads ? pair.first : pair.second;
  preference.option_b = first_leads ? pair.second : pair.first;
  preference.chose_a = std::max(first, second);
  preference.chose_b = std::min(first, second);
  preference.neither = counts.neither;
  const long decided = preference.chose_a + preference.chose_b;
  if (decided == 0) {
    preference.binomial.unavailable = "no choice between the two (only 'neither')";
    preference.chi_square.unavailable = "no choice between the two: expected counts are zero";
  } else {
    preference.binomial = binomial_test_two_sided(preference.chose_a, decided);
    preference.share_a_interval = clopper_pearson_interval(preference.chose_a, decided);
    if (decided >= kChiSquareMinimumAnswers) {
      preference.chi_square = chi_square_goodness_of_fit({preference.chose_a, preference.chose_b});
    } else {
      preference.chi_square.unavailable = std::to_string(decided) + " answers: expected counts below 5, the exact binomial test stands";
    }
  }
  return preference;
}

}  // namespace

double PairPreference::share_a() const {
  const long decided = chose_a + chose_b;
  return decided > 0 ? static_cast<double>(chose_a) / static_cast<double>(decided) : 0.0;
}

double PairPreference::neither_share() const {
  const long all = chose_a + chose_b + neither;
  return all > 0 ? static_cast<double>(neither) / static_cast<double>(all) : 0.0;
}

ForcedChoiceAnalysis analyse_forced_choice(const LoadedData& data, const std::function<bool(const LoadedTrial&)>& skip) {
  ForcedChoiceAnalysis analysis;
  std::map<std::pair<std::string, PairKey>, Counts> by_group;
  std::map<std::pair<std::string, PairKey>, Counts> by_pool;
  std::vector<std::string> group_order;
  std::map<std::string, std::pair<long, long>> scored;  // group -> (correct, trials)
  std::vector<std::string> scored_order;
  long unusable = 0;
  for (const LoadedSession& session : data.sessions) {
    for (const LoadedTrial& trial : session.trials) {
      if (trial.record.procedure != "forced_choice") continue;
      // Percent correct over every scored trial, a graded variable's too (a scored 2-AFC).
      if (trial.record.correct && (*trial.record.correct == 0 || *trial.record.correct == 1)) {
        std::string pool;
        const std::string group = group_of(trial, pool);
        if (!scored.contains(group)) scored_order.push_back(group);
        scored[group].first += *trial.record.correct;
        ++scored[group].second;
      }
      if (skip && skip(trial)) continue;
      ++analysis.trials;
      std::vector<std::string> options;
      for (const std::string& position : kPositions) {
        if (const std::string* option = option_at(trial, position)) options.push_back(*option);
      }
      if (options.size() != 2 || options[0] == options[1]) {
        ++unusable;
        continue;
      }
      std::string chosen;
      if (const std::string* named = option_at(trial, trial.record.response);
          named != nullptr && std::find(kPositions.begin(), kPositions.end(), trial.record.response) != kPositions.end()) {
        chosen = *named;
      } else {
        chosen = trial.record.response;
      }
      const bool neither = chosen == "neither";
      if (!neither && chosen != options[0] && chosen != options[1]) {
        ++unusable;  // "abort" or an answer outside the options
        continue;
      }
      std::sort(options.begin(), options.end());
      const PairKey pair{options[0], options[1]};
      std::string pool;
      const std::string group = group_of(trial, pool);
      if (std::find(group_order.begin(), group_order.end(), group) == group_order.end()) group_order.push_back(group);
      for (auto* counts : {&by_group[{group, pair}], &by_pool[{pool, pair}]}) {
        if (neither) {
          ++counts->neither;
        } else {
          ++counts->chosen[chosen];
        }
      }
    }
  }
  for (const std::string& group : group_order) {
    for (const auto& [key, counts] : by_group) {
      if (key.first == group) analysis.groups.push_back(make_preference(group, key.second, counts));
    }
  }
  const auto share = [](const std::string& group, long correct, long trials) {
    ScoredShare result{group, correct, trials, clopper_pearson_interval(correct, trials), binomial_test_two_sided(correct, trials)};
    return result;
  };
  long all_correct = 0, all_trials = 0;
  // Per group up to kScoredGroupsListed groups (a design whose every row is a group would list
  // each row), always the total when there is more than one group.
  constexpr std::size_t kScoredGroupsListed = 8;
  for (const std::string& group : scored_order) {
    const auto& [correct, trials] = scored[group];
    if (scored_order.size() <= kScoredGroupsListed) analysis.scored.push_back(share(group, correct, trials));
    all_correct += correct;
    all_trials += trials;
  }
  if (scored_order.size() > 1) analysis.scored.push_back(share("all scored trials", all_correct, all_trials));
  for (const auto& [key, counts] : by_pool) analysis.pooled.push_back(make_preference("pooled: " + key.first, key.second, counts));
  if (unusable > 0) {
    analysis.notes.push_back(std::to_string(unusable) +
                             " forced-choice trial(s) left out: no two distinct options at left/right (or first/second) in the condition, "
                             "or the response names neither option (e.g. an aborted trial)");
  }
  return analysis;
}

}  // namespace glarelab::analysis

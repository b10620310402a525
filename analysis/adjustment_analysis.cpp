#include "analysis/adjustment_analysis.h"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <optional>

namespace glarelab::analysis {
namespace {

std::string first_value(const LoadedTrial& trial, std::initializer_list<const char*> keys, const std::string& fallback) {
  for (const char* key : keys) {
    if (const std::string* value = trial.condition_value(key)) return *value;
  }
  return fallback;
}

std::optional<double> perceived_value(const LoadedTrial& trial) {
  if (!trial.adjustments.empty()) {
    double sum = 0.0;
    for (const AdjustmentRecord& a : trial.adjustments) sum += a.value;
    return sum / static_cast<double>(trial.adjustments.size());
  }
  if (trial.record.intensity) return trial.record.intensity;
  const std::string& text = trial.record.response;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (!text.empty() && end == text.c_str() + text.size()) return value;
  return std::nullopt;
}

void add_unique(std::vector<std::string>& list, const std::string& value) {
  if (std::find(list.begin(), list.end(), value) == list.end()) list.push_back(value);
}

}  // namespace

AdjustmentAnalysis analyse_adjustments(const LoadedData& data) {
  AdjustmentAnalysis analysis;
  // participant -> (condition, target) -> values
  std::map<std::string, std::map<std::pair<std::string, std::string>, std::vector<double>>> values;
  std::vector<std::string> participants;
  long without_value = 0;
  for (const LoadedSession& session : data.sessions) {
    for (const LoadedTrial& trial : session.trials) {
      if (trial.record.procedure != "adjustment") continue;
      ++analysis.trials;
      const auto value = perceived_value(trial);
      if (!value) {
        ++without_value;
        continue;
      }
      const std::string condition = first_value(trial, {"glare", "condition", "name"}, "(all)");
      const std::string target = first_value(trial, {"target_level", "target_cd_m2", "target"}, "(all)");
      add_unique(analysis.conditions, condition);
      add_unique(analysis.targets, target);
      // Participants are identified by their code, so two sessions of one person pool.
      add_unique(participants, session.record.participant);
      values[session.record.participant][{condition, target}].push_back(*value);
    }
  }
  if (without_value > 0) {
    analysis.notes.push_back(std::to_string(without_value) + " adjustment trial(s) without an adjusted value left out");
  }
  auto participant_mean = [&](const std::string& participant, const std::string& condition,
                              const std::string& target) -> std::optional<double> {
    const auto& cells = values[participant];
    const auto found = cells.find({condition, target});
    if (found == cells.end() || found->second.empty()) return std::nullopt;
    return mean_and_standard_error(found->second).mean;
  };
  for (const std::string& target : analysis.targets) {
    for (const std::string& condition : analysis.conditions) {
      std::vector<double> means;
      for (const std::string& participant : participants) {
        if (auto mean = participant_mean(participant, condition, target)) means.push_back(*mean);
      }
      if (means.empty()) {
        analysis.notes.push_back("empty cell: no adjustments for condition '" + condition + "' at target '" + target + "'");
        continue;
      }
      analysis.cells.push_back({condition, target, mean_and_standard_error(means)});
    }
    // Only conditions measured at this target enter its ANOVA; participants need all of them.
    std::vector<std::string> present;
    for (const AdjustmentCell& cell : analysis.cells) {
      if (cell.target == target) present.push_back(cell.condition);
    }
    std::vector<std::vector<double>> scores;
    for (const std::string& participant : participants) {
      std::vector<double> row;
      for (const std::string& condition : present) {
        if (auto mean = participant_mean(participant, condition, target)) row.push_back(*mean);
      }
      if (row.size() == present.size()) scores.push_back(row);
    }
    if (present.size() >= 2) analysis.anovas.push_back({target, present, repeated_measures_anova(scores)});
    for (std::size_t a = 0; a < present.size(); ++a) {
      for (std::size_t b = a + 1; b < present.size(); ++b) {
        std::vector<double> first;
        std::vector<double> second;
        for (const std::string& participant : participants) {
          auto x = participant_mean(participant, present[a], target);
          auto y = participant_mean(participant, present[b], target);
          if (x && y) {
            first.push_back(*x);
            second.push_back(*y);
          }
        }
        analysis.paired.push_back({target, present[a], present[b], first.size(), paired_t_test(first, second)});
      }
    }
  }
  return analysis;
}

}  // namespace glarelab::analysis

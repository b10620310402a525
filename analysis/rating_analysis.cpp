#include "analysis/rating_analysis.h"

#include <algorithm>
#include <cstdlib>

#include "analysis/statistics.h"

namespace glarelab::analysis {
namespace {

std::optional<double> as_number(const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size()) return std::nullopt;
  return value;
}

}  // namespace

RatingAnalysis analyse_ratings(const LoadedData& data) {
  RatingAnalysis analysis;
  std::vector<std::string> order;
  std::map<std::string, std::vector<std::string>> answers;
  for (const LoadedSession& session : data.sessions) {
    for (const LoadedTrial& trial : session.trials) {
      if (trial.record.procedure != "rating") continue;
      ++analysis.trials;
      if (trial.record.response.empty() || trial.record.response == "abort") continue;
      const std::string* name = trial.condition_value("name");
      const std::string condition = name != nullptr ? *name : trial.record.condition;
      if (answers.find(condition) == answers.end()) order.push_back(condition);
      answers[condition].push_back(trial.record.response);
    }
  }
  for (const std::string& condition : order) {
    const auto& list = answers[condition];
    RatingDistribution distribution;
    distribution.condition = condition;
    distribution.answers = static_cast<long>(list.size());
    std::map<std::string, long> counts;
    std::vector<double> numbers;
    for (const std::string& answer : list) {
      ++counts[answer];
      if (auto number = as_number(answer)) numbers.push_back(*number);
    }
    for (const auto& entry : counts) distribution.categories.push_back(entry);
    if (numbers.size() == list.size()) {
      std::sort(distribution.categories.begin(), distribution.categories.end(),
                [](const auto& a, const auto& b) { return *as_number(a.first) < *as_number(b.first); });
      distribution.mean = mean_and_standard_error(numbers).mean;
      distribution.median = median(numbers);
    }
    analysis.conditions.push_back(std::move(distribution));
  }
  return analysis;
}

}  // namespace glarelab::analysis

#include "analysis/rating_analysis.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <toml++/toml.h>

#include "analysis/statistics.h"
#include "core/text_limits.h"

namespace glarelab::analysis {
namespace {

std::optional<double> as_number(const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  // "nan" and "inf" parse as numbers but are not ratings.
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

struct Answer {
  std::string participant;
  std::string condition;
  std::string category;
  std::string value;
};

template <typename T>
void remember(std::vector<T>& order, const T& item) {
  if (std::find(order.begin(), order.end(), item) == order.end()) order.push_back(item);
}

// Moves the items of `order` that `preferred` names to the front, in `preferred`'s order.
void put_first(std::vector<std::string>& order, const std::vector<std::string>& preferred) {
  std::vector<std::string> sorted;
  for (const std::string& item : preferred)
    if (std::find(order.begin(), order.end(), item) != order.end()) sorted.push_back(item);
  for (const std::string& item : order)
    if (std::find(sorted.begin(), sorted.end(), item) == sorted.end()) sorted.push_back(item);
  order = std::move(sorted);
}

// Answer values in scale order: numeric order when every value is a number, else text order.
void sort_scale(std::vector<std::string>& values, bool numeric) {
  if (numeric) {
    std::stable_sort(values.begin(), values.end(),
                     [](const std::string& a, const std::string& b) { return *as_number(a) < *as_number(b); });
  } else {
    std::sort(values.begin(), values.end());
  }
}

RatingDistribution distribution_of(const std::string& condition, const std::string& category,
                                   const std::vector<std::string>& values, const std::vector<std::string>& scale,
                                   bool numeric) {
  RatingDistribution distribution;
  distribution.condition = condition;
  distribution.category = category;
  distribution.answers = static_cast<long>(values.size());
  for (const std::string& point : scale) {
    distribution.categories.emplace_back(point, static_cast<long>(std::count(values.begin(), values.end(), point)));
  }
  if (numeric && !values.empty()) {
    std::vector<double> numbers;
    for (const std::string& value : values) numbers.push_back(*as_number(value));
    distribution.mean = mean_and_standard_error(numbers).mean;
    distribution.median = median(numbers);
  }
  return distribution;
}

RatingComparison compare_category(const std::string& category, const std::vector<Answer>& answers,
                                  const std::vector<std::string>& condition_order) {
  RatingComparison comparison;
  comparison.category = category;
  std::vector<std::string> participants;
  // (participant, condition) -> the participant's ratings of that condition on this category.
  std::map<std::pair<std::string, std::string>, std::vector<double>> ratings;
  for (const Answer& answer : answers) {
    if (answer.category != category) continue;
    remember(participants, answer.participant);
    ratings[{answer.participant, answer.condition}].push_back(*as_number(answer.value));
  }
  for (const std::string& condition : condition_order)
    if (std::any_of(answers.begin(), answers.end(),
                    [&](const Answer& a) { return a.category == category && a.condition == condition; }))
      comparison.conditions.push_back(condition);
  for (const std::string& participant : participants) {
    std::vector<double> row;
    for (const std::string& condition : comparison.conditions) {
      const auto found = ratings.find({participant, condition});
      if (found == ratings.end()) break;
      row.push_back(mean_and_standard_error(found->second).mean);
    }
    if (row.size() == comparison.conditions.size()) {
      comparison.participants.push_back(participant);
      comparison.scores.push_back(std::move(row));
    } else {
      comparison.left_out.push_back(participant);
    }
  }
  const std::size_t k = comparison.conditions.size();
  if (k < 2) {
    comparison.unavailable = "only one condition was rated on this category: nothing to compare";
  } else if (comparison.participants.empty()) {
    comparison.unavailable = "no participant rated every condition of this category";
  } else if (k == 2) {
    std::vector<double> first, second;
    for (const auto& row : comparison.scores) {
      first.push_back(row[0]);
      second.push_back(row[1]);
    }
    comparison.wilcoxon = wilcoxon_signed_rank(first, second);
  } else {
    comparison.friedman = friedman_test(comparison.scores);
    if (comparison.friedman->ok())
      comparison.post_hoc = rating_post_hoc(comparison.conditions, comparison.scores, comparison.friedman->p_value);
  }
  return comparison;
}

}  // namespace

StoredRatingDesign stored_rating_design(const std::string& config_toml) {
  StoredRatingDesign design;
  toml::table root;
  if (toml_limit_fault(config_toml)) return design;  // toml++ would recurse past the stack
  try {
    root = toml::parse(config_toml);
  } catch (const toml::parse_error&) {
    return design;
  }
  const std::optional<std::int64_t> points = root["procedure"]["scale_points"].value<std::int64_t>();
  if (points && *points >= 2 && *points <= 99) design.scale_points = static_cast<int>(*points);
  if (const toml::array* categories = root["procedure"]["categories"].as_array()) {
    for (const toml::node& category : *categories)
      if (const auto text = category.value<std::string>()) design.categories.push_back(*text);
  }
  if (const toml::array* rows = root["conditions"]["rows"].as_array()) {
    for (const toml::node& row : *rows) {
      if (const toml::table* table = row.as_table())
        if (const auto name = (*table)["name"].value<std::string>()) design.conditions.push_back(*name);
    }
  }
  return design;
}

RatingAnalysis analyse_ratings(const LoadedData& data) {
  RatingAnalysis analysis;
  std::vector<Answer> answers;
  std::vector<std::string> condition_order;
  std::vector<std::pair<std::string, std::string>> cell_order;  // (category, condition)
  int scale_points = 0;
  std::vector<std::string> stored_categories, stored_conditions;
  for (const LoadedSession& session : data.sessions) {
    bool rated = false;
    for (const LoadedTrial& trial : session.trials) {
      if (trial.record.procedure != "rating") continue;
      ++analysis.trials;
      rated = true;
      if (trial.record.response.empty() || trial.record.response == "abort") continue;
      const std::string* name = trial.condition_value("name");
      const std::string* category = trial.condition_value("category");
      Answer answer{session.record.participant, name != nullptr ? *name : trial.record.condition,
                    category != nullptr ? *category : "", trial.record.response};
      remember(condition_order, answer.condition);
      remember(analysis.category_order, answer.category);
      remember(cell_order, {answer.category, answer.condition});
      answers.push_back(std::move(answer));
    }
    if (rated) {
      const StoredRatingDesign design = stored_rating_design(session.record.config);
      scale_points = std::max(scale_points, design.scale_points);
      for (const std::string& category : design.categories) remember(stored_categories, category);
      for (const std::string& condition : design.conditions) remember(stored_conditions, condition);
    }
  }
  put_first(analysis.category_order, stored_categories);
  put_first(condition_order, stored_conditions);
  bool numeric = !answers.empty();
  std::vector<std::string> observed;
  for (const Answer& answer : answers) {
    numeric = numeric && as_number(answer.value).has_value();
    remember(observed, answer.value);
  }
  // Every point of the stored scale appears in the per-category distributions (Figs. 7.2-7.7
  // show the unchosen points too).
  analysis.scale = observed;
  if (numeric) {
    for (int point = 1; point <= scale_points; ++point) {
      const std::string text = std::to_string(point);
      const bool present = std::any_of(analysis.scale.begin(), analysis.scale.end(),
                                       [&](const std::string& value) { return *as_number(value) == point; });
      if (!present) analysis.scale.push_back(text);
    }
  }
  sort_scale(analysis.scale, numeric);
  sort_scale(observed, numeric);

  for (const std::string& condition : condition_order) {
    std::vector<std::string> values;
    for (const Answer& answer : answers)
      if (answer.condition == condition) values.push_back(answer.value);
    std::vector<std::string> seen;
    for (const std::string& value : observed)
      if (std::find(values.begin(), values.end(), value) != values.end()) seen.push_back(value);
    analysis.conditions.push_back(distribution_of(condition, "", values, seen, numeric));
  }
  for (const std::string& category : analysis.category_order) {
    for (const std::string& condition : condition_order) {
      if (std::find(cell_order.begin(), cell_order.end(), std::make_pair(category, condition)) == cell_order.end()) continue;
      std::vector<std::string> values;
      for (const Answer& answer : answers)
        if (answer.category == category && answer.condition == condition) values.push_back(answer.value);
      analysis.cells.push_back(distribution_of(condition, category, values, analysis.scale, numeric));
    }
  }
  if (!numeric && !answers.empty()) {
    analysis.notes.push_back("not every rating is a number: no means, medians or rank tests");
  } else {
    for (const std::string& category : analysis.category_order)
      analysis.comparisons.push_back(compare_category(category, answers, condition_order));
  }
  return analysis;
}

}  // namespace glarelab::analysis

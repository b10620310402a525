#include "analysis/rating_post_hoc.h"

#include <algorithm>
#include <numeric>

namespace glarelab::analysis {

std::vector<double> holm_adjusted_p(const std::vector<double>& p_values) {
  const std::size_t m = p_values.size();
  std::vector<std::size_t> order(m);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return p_values[a] < p_values[b]; });
  std::vector<double> adjusted(m, 1.0);
  double running = 0.0;  // the step-down maximum keeps the adjusted values in the p-values' order
  for (std::size_t i = 0; i < m; ++i) {
    running = std::max(running, static_cast<double>(m - i) * p_values[order[i]]);
    adjusted[order[i]] = std::min(1.0, running);
  }
  return adjusted;
}

std::vector<RatingPairTest> rating_post_hoc(const std::vector<std::string>& conditions,
                                            const std::vector<std::vector<double>>& scores, double friedman_p) {
  std::vector<RatingPairTest> pairs;
  if (friedman_p > kPostHocAlpha) return pairs;
  for (std::size_t i = 0; i < conditions.size(); ++i)
    for (std::size_t j = i + 1; j < conditions.size(); ++j) {
      std::vector<double> first, second;
      for (const auto& row : scores) {
        first.push_back(row[i]);
        second.push_back(row[j]);
      }
      pairs.push_back({conditions[i], conditions[j], wilcoxon_signed_rank(first, second), 1.0});
    }
  std::vector<double> p_values;
  for (const RatingPairTest& pair : pairs)
    if (pair.wilcoxon.ok()) p_values.push_back(pair.wilcoxon.p_value);
  const std::vector<double> adjusted = holm_adjusted_p(p_values);
  std::size_t next = 0;
  for (RatingPairTest& pair : pairs)
    if (pair.wilcoxon.ok()) pair.p_holm = adjusted[next++];
  return pairs;
}

}  // namespace glarelab::analysis

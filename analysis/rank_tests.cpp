#include "analysis/rank_tests.h"

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <numeric>

namespace glarelab::analysis {
namespace {

// Pairs at most this many go exact under WilcoxonMethod::automatic (SciPy 1.10's limit).
constexpr std::size_t kExactLimit = 50;

// Sum over tie groups of t^3 - t.
double tie_sum(const std::vector<double>& values) {
  double sum = 0.0;
  for (const std::size_t t : tie_group_sizes(values)) {
    const auto size = static_cast<double>(t);
    sum += size * size * size - size;
  }
  return sum;
}

// Null distribution of the signed-rank sum R+ of n untied ranks: count[s] = number of subsets
// of {1..n} summing to s (each sign pattern has probability 2^-n). For the n <= 50 that go exact
// by default the counts stay below 2^50, so doubles hold them exactly; an explicitly exact test
// of more pairs rounds them (relative error about 1e-16 each).
std::vector<double> signed_rank_counts(std::size_t n) {
  const std::size_t top = n * (n + 1) / 2;
  std::vector<double> count(top + 1, 0.0);
  count[0] = 1.0;
  std::size_t reached = 0;
  for (std::size_t rank = 1; rank <= n; ++rank) {
    reached += rank;
    for (std::size_t s = reached; s >= rank; --s) count[s] += count[s - rank];
  }
  return count;
}

}  // namespace

std::vector<double> average_ranks(const std::vector<double>& values) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return values[i] < values[j]; });
  std::vector<double> ranks(values.size(), 0.0);
  for (std::size_t start = 0; start < order.size();) {
    std::size_t end = start + 1;
    while (end < order.size() && values[order[end]] == values[order[start]]) ++end;
    // Positions start..end-1 hold ranks start+1..end; each gets their mean.
    const double midrank = 0.5 * static_cast<double>(start + 1 + end);
    for (std::size_t i = start; i < end; ++i) ranks[order[i]] = midrank;
    start = end;
  }
  return ranks;
}

std::vector<std::size_t> tie_group_sizes(const std::vector<double>& values) {
  std::vector<double> sorted = values;
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::size_t> sizes;
  for (std::size_t start = 0; start < sorted.size();) {
    std::size_t end = start + 1;
    while (end < sorted.size() && sorted[end] == sorted[start]) ++end;
    if (end - start > 1) sizes.push_back(end - start);
    start = end;
  }
  return sizes;
}

WilcoxonSignedRank wilcoxon_signed_rank(const std::vector<double>& a, const std::vector<double>& b,
                                        WilcoxonMethod method, bool continuity_correction) {
  WilcoxonSignedRank result;
  result.continuity_correction = continuity_correction;
  if (a.size() != b.size()) {
    result.unavailable = "unequal numbers of paired values";
    return result;
  }
  result.pairs = a.size();
  std::vector<double> differences;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double difference = a[i] - b[i];
    if (!std::isfinite(difference)) {
      result.unavailable = "a paired value is not a finite number";
      return result;
    }
    if (difference == 0.0) {
      ++result.zero_differences;
    } else {
      differences.push_back(difference);
    }
  }
  result.ranked = differences.size();
  if (differences.empty()) {
    result.unavailable = result.pairs == 0 ? "no pairs"
                                           : "every one of the " + std::to_string(result.pairs) +
                                                 " pairs is equal (all differences are zero)";
    return result;
  }
  std::vector<double> magnitudes(differences.size());
  for (std::size_t i = 0; i < differences.size(); ++i) magnitudes[i] = std::abs(differences[i]);
  const std::vector<double> ranks = average_ranks(magnitudes);
  for (std::size_t i = 0; i < differences.size(); ++i)
    (differences[i] > 0.0 ? result.rank_sum_positive : result.rank_sum_negative) += ranks[i];
  result.statistic = std::min(result.rank_sum_positive, result.rank_sum_negative);

  const double ties = tie_sum(magnitudes);
  const bool exact_possible = result.zero_differences == 0 && ties == 0.0;
  if (method == WilcoxonMethod::exact && !exact_possible) {
    result.unavailable = result.zero_differences > 0
                             ? "the exact signed-rank distribution does not allow zero differences (" +
                                   std::to_string(result.zero_differences) + " pairs equal)"
                             : "the exact signed-rank distribution does not allow tied differences";
    return result;
  }
  result.exact = method == WilcoxonMethod::exact ||
                 (method == WilcoxonMethod::automatic && exact_possible && result.pairs <= kExactLimit);
  const std::size_t n = result.ranked;
  const auto count = static_cast<double>(n);
  if (result.exact) {
    // R+ is an integer here (no ties); SciPy: 1 at the middle value, else twice the smaller tail.
    const std::vector<double> counts = signed_rank_counts(n);
    const auto r = static_cast<std::size_t>(std::lround(result.rank_sum_positive));
    const std::size_t top = counts.size() - 1;
    if (r == top / 2) {
      result.p_value = 1.0;
    } else {
      const double total = std::ldexp(1.0, static_cast<int>(n));
      double lower = 0.0;
      double upper = 0.0;
      for (std::size_t s = 0; s <= r; ++s) lower += counts[s];
      for (std::size_t s = r; s <= top; ++s) upper += counts[s];
      result.p_value = std::clamp(2.0 * std::min(lower, upper) / total, 0.0, 1.0);
    }
    return result;
  }
  const double mean = 0.25 * count * (count + 1.0);
  const double variance = (count * (count + 1.0) * (2.0 * count + 1.0) - 0.5 * ties) / 24.0;
  if (!(variance > 0.0)) {
    result.unavailable = "the signed ranks have no variance";
    return result;
  }
  double correction = 0.0;
  if (continuity_correction) {
    const double offset = result.statistic - mean;
    correction = offset > 0.0 ? 0.5 : offset < 0.0 ? -0.5 : 0.0;
  }
  result.z = (result.statistic - mean - correction) / std::sqrt(variance);
  result.p_value = std::min(1.0, 2.0 * boost::math::cdf(boost::math::complement(boost::math::normal_distribution<double>(),
                                                                                 std::abs(result.z))));
  return result;
}

FriedmanTest friedman_test(const std::vector<std::vector<double>>& scores) {
  FriedmanTest result;
  result.subjects = scores.size();
  result.conditions = scores.empty() ? 0 : scores.front().size();
  const std::size_t n = result.subjects;
  const std::size_t k = result.conditions;
  if (k < 3) {
    result.unavailable = "the Friedman test needs at least 3 conditions (found " + std::to_string(k) +
                         "; two are compared with the signed-rank test)";
    return result;
  }
  if (n < 2) {
    result.unavailable = "the Friedman test needs at least 2 participants who rated every condition (found " +
                         std::to_string(n) + ")";
    return result;
  }
  std::vector<double> rank_sums(k, 0.0);
  double ties = 0.0;
  for (const std::vector<double>& row : scores) {
    if (row.size() != k) {
      result.unavailable = "incomplete rows";
      return result;
    }
    for (double value : row) {
      if (!std::isfinite(value)) {
        result.unavailable = "a score is not a finite number";
        return result;
      }
    }
    const std::vector<double> ranks = average_ranks(row);
    for (std::size_t j = 0; j < k; ++j) rank_sums[j] += ranks[j];
    ties += tie_sum(row);
  }
  const auto nn = static_cast<double>(n);
  const auto kk = static_cast<double>(k);
  result.tie_correction = 1.0 - ties / (kk * (kk * kk - 1.0) * nn);
  if (!(result.tie_correction > 1e-12)) {
    result.unavailable = "every participant gave every condition the same score (no ranks to compare)";
    return result;
  }
  double sum_squares = 0.0;
  for (double sum : rank_sums) sum_squares += sum * sum;
  result.chi_square = (12.0 / (kk * nn * (kk + 1.0)) * sum_squares - 3.0 * nn * (kk + 1.0)) / result.tie_correction;
  result.chi_square = std::max(0.0, result.chi_square);  // rounding can leave -1e-15 when the sums are equal
  result.df = kk - 1.0;
  result.p_value = boost::math::cdf(boost::math::complement(boost::math::chi_squared_distribution<double>(result.df),
                                                            result.chi_square));
  result.kendall_w = result.chi_square / (nn * (kk - 1.0));
  return result;
}

}  // namespace glarelab::analysis

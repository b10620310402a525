#include "analysis/statistics.h"

#include <algorithm>
#include <boost/math/distributions/beta.hpp>
#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace glarelab::analysis {
namespace {

TestResult unavailable(std::string why) {
  TestResult result;
  result.unavailable = std::move(why);
  return result;
}

}  // namespace

ProportionInterval clopper_pearson_interval(long successes, long trials, double confidence) {
  const double tail = 0.5 * (1.0 - confidence);
  const double k = static_cast<double>(successes), n = static_cast<double>(trials);
  ProportionInterval interval;
  if (successes > 0) interval.low = boost::math::quantile(boost::math::beta_distribution<double>(k, n - k + 1.0), tail);
  if (successes < trials) interval.high = boost::math::quantile(boost::math::beta_distribution<double>(k + 1.0, n - k), 1.0 - tail);
  return interval;
}

TestResult binomial_test_two_sided(long successes, long trials, double p) {
  if (trials <= 0) return unavailable("no trials");
  if (successes < 0 || successes > trials) return unavailable("successes outside 0..trials");
  if (!(p > 0.0 && p < 1.0)) return unavailable("probability must lie in (0, 1)");
  const boost::math::binomial_distribution<double> distribution(static_cast<double>(trials), p);
  const double observed = boost::math::pdf(distribution, static_cast<double>(successes));
  // Outcomes at most as likely as the observed one (with the relative tolerance R and SciPy use,
  // so that ties such as k and n - k at p = 1/2 both count).
  const double limit = observed * (1.0 + 1e-7);
  double sum = 0.0;
  for (long k = 0; k <= trials; ++k) {
    const double probability = boost::math::pdf(distribution, static_cast<double>(k));
    if (probability <= limit) sum += probability;
  }
  TestResult result;
  result.statistic = static_cast<double>(successes);
  result.df1 = static_cast<double>(trials);
  result.p_value = std::min(1.0, sum);
  return result;
}

TestResult chi_square_goodness_of_fit(const std::vector<long>& observed, const std::vector<double>& expected_proportions) {
  if (observed.size() < 2) return unavailable("a chi-square test needs at least 2 categories");
  if (!expected_proportions.empty() && expected_proportions.size() != observed.size()) {
    return unavailable("expected proportions do not match the categories");
  }
  const long total = std::accumulate(observed.begin(), observed.end(), 0L);
  if (total == 0) return unavailable("no observations (all expected counts are zero)");
  double chi2 = 0.0;
  for (std::size_t i = 0; i < observed.size(); ++i) {
    const double proportion =
        expected_proportions.empty() ? 1.0 / static_cast<double>(observed.size()) : expected_proportions[i];
    const double expected = proportion * static_cast<double>(total);
    if (!(expected > 0.0)) return unavailable("an expected count is zero");
    const double difference = static_cast<double>(observed[i]) - expected;
    chi2 += difference * difference / expected;  // Pearson (1900)
  }
  TestResult result;
  result.statistic = chi2;
  result.df1 = static_cast<double>(observed.size() - 1);
  result.p_value = boost::math::cdf(boost::math::complement(boost::math::chi_squared_distribution<double>(result.df1), chi2));
  return result;
}

TestResult paired_t_test(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return unavailable("unequal numbers of paired values");
  if (a.size() < 2) return unavailable("a paired t-test needs at least 2 pairs (found " + std::to_string(a.size()) + ")");
  std::vector<double> differences(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) differences[i] = a[i] - b[i];
  const MeanSe summary = mean_and_standard_error(differences);
  if (!(*summary.standard_error > 0.0)) return unavailable("all paired differences are equal (zero variance)");
  TestResult result;
  result.statistic = summary.mean / *summary.standard_error;
  result.df1 = static_cast<double>(a.size() - 1);
  result.p_value = 2.0 * boost::math::cdf(boost::math::complement(boost::math::students_t_distribution<double>(result.df1),
                                                                  std::abs(result.statistic)));
  result.p_value = std::min(1.0, result.p_value);
  return result;
}

MeanSe mean_and_standard_error(const std::vector<double>& values) {
  MeanSe result;
  result.n = values.size();
  if (values.empty()) return result;
  result.mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
  if (values.size() >= 2) result.standard_error = standard_deviation(values) / std::sqrt(static_cast<double>(values.size()));
  return result;
}

double standard_deviation(const std::vector<double>& values) {
  if (values.size() < 2) return 0.0;
  const double mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
  double sum = 0.0;
  for (double value : values) sum += (value - mean) * (value - mean);
  return std::sqrt(sum / static_cast<double>(values.size() - 1));
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

RepeatedMeasuresAnova repeated_measures_anova(const std::vector<std::vector<double>>& scores) {
  RepeatedMeasuresAnova result;
  result.subjects = scores.size();
  result.levels = scores.empty() ? 0 : scores.front().size();
  const std::size_t n = result.subjects;
  const std::size_t k = result.levels;
  if (k < 2) {
    result.unavailable = "a repeated-measures ANOVA needs at least 2 levels (found " + std::to_string(k) + ")";
    return result;
  }
  if (n < 2) {
    result.unavailable = "a repeated-measures ANOVA needs at least 2 participants with every level (found " +
                         std::to_string(n) + ")";
    return result;
  }
  for (const auto& row : scores) {
    if (row.size() != k) {
      result.unavailable = "incomplete rows";
      return result;
    }
  }
  // Sums of squares of the subjects x levels layout (e.g. Field 2009, ch. 13).
  double grand = 0.0;
  std::vector<double> level_mean(k, 0.0);
  std::vector<double> subject_mean(n, 0.0);
  for (std::size_t s = 0; s < n; ++s) {
    for (std::size_t l = 0; l < k; ++l) {
      grand += scores[s][l];
      level_mean[l] += scores[s][l] / static_cast<double>(n);
      subject_mean[s] += scores[s][l] / static_cast<double>(k);
    }
  }
  grand /= static_cast<double>(n * k);
  double ss_condition = 0.0;
  double ss_subjects = 0.0;
  double ss_total = 0.0;
  for (std::size_t l = 0; l < k; ++l) ss_condition += static_cast<double>(n) * std::pow(level_mean[l] - grand, 2);
  for (std::size_t s = 0; s < n; ++s) ss_subjects += static_cast<double>(k) * std::pow(subject_mean[s] - grand, 2);
  for (const auto& row : scores) {
    for (double value : row) ss_total += (value - grand) * (value - grand);
  }
  const double ss_error = std::max(0.0, ss_total - ss_condition - ss_subjects);
  result.df_condition = static_cast<double>(k - 1);
  result.df_error = static_cast<double>((k - 1) * (n - 1));
  const double ms_error = ss_error / result.df_error;
  if (!(ms_error > 1e-300)) {
    result.unavailable = "the error variance is zero (every participant shows the same differences between levels)";
    return result;
  }
  result.f = (ss_condition / result.df_condition) / ms_error;
  result.p_value = boost::math::cdf(boost::math::complement(
      boost::math::fisher_f_distribution<double>(result.df_condition, result.df_error), result.f));

  // Greenhouse-Geisser epsilon (Box 1954; Greenhouse & Geisser 1959): with S the k x k sample
  // covariance of the levels and S* its double-centred form,
  // epsilon = (trace S*)^2 / ((k - 1) * sum_ij S*_ij^2).
  std::vector<std::vector<double>> covariance(k, std::vector<double>(k, 0.0));
  for (std::size_t i = 0; i < k; ++i) {
    for (std::size_t j = 0; j < k; ++j) {
      double sum = 0.0;
      for (std::size_t s = 0; s < n; ++s) sum += (scores[s][i] - level_mean[i]) * (scores[s][j] - level_mean[j]);
      covariance[i][j] = sum / static_cast<double>(n - 1);
    }
  }
  std::vector<double> row_mean(k, 0.0);
  double all_mean = 0.0;
  for (std::size_t i = 0; i < k; ++i) {
    for (std::size_t j = 0; j < k; ++j) row_mean[i] += covariance[i][j] / static_cast<double>(k);
    all_mean += row_mean[i] / static_cast<double>(k);
  }
  double trace = 0.0;
  double sum_squares = 0.0;
  for (std::size_t i = 0; i < k; ++i) {
    for (std::size_t j = 0; j < k; ++j) {
      const double centred = covariance[i][j] - row_mean[i] - row_mean[j] + all_mean;
      if (i == j) trace += centred;
      sum_squares += centred * centred;
    }
  }
  result.epsilon_gg = sum_squares > 0.0 ? trace * trace / (static_cast<double>(k - 1) * sum_squares) : 1.0;
  // Bounded by 1/(k-1) <= epsilon <= 1 (Greenhouse & Geisser 1959).
  result.epsilon_gg = std::clamp(result.epsilon_gg, 1.0 / static_cast<double>(k - 1), 1.0);
  result.p_value_gg = boost::math::cdf(boost::math::complement(
      boost::math::fisher_f_distribution<double>(result.df_condition * result.epsilon_gg,
                                                 result.df_error * result.epsilon_gg),
      result.f));
  return result;
}

std::string format_p(double p) {
  if (p < 0.0001) return "p < 0.0001";
  char text[32];
  std::snprintf(text, sizeof text, "p = %.4f", p);
  return text;
}

}  // namespace glarelab::analysis

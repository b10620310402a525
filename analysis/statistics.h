#pragma once
// Classical tests used by the analysis, on top of Boost.Math's distributions (no hand-written
// special functions). Each result either carries its numbers or, when the data cannot support
// the test, a statement saying why (`unavailable`), never NaN.
#include <optional>
#include <string>
#include <vector>

namespace glarelab::analysis {

struct TestResult {
  std::string unavailable;  // non-empty: why there is no result
  double statistic = 0.0;   // chi2, t or F
  double df1 = 0.0;
  double df2 = 0.0;  // F only
  double p_value = 1.0;
  bool ok() const { return unavailable.empty(); }
};

// Exact two-sided binomial test of `successes` of `trials` against probability `p`: the sum of
// the probabilities of all outcomes no more likely than the observed one (the definition used by
// R's binom.test and SciPy's binomtest, with their relative tolerance 1 + 1e-7).
TestResult binomial_test_two_sided(long successes, long trials, double p = 0.5);

// The Clopper & Pearson (1934) "exact" interval of a binomial proportion: the probabilities p
// at which observing `successes` or more (lower end) or `successes` or fewer (upper end) of
// `trials` has probability (1 - confidence) / 2, from the beta quantiles they equal:
// low = B^-1((1 - c)/2; k, n - k + 1) (0 when k = 0), high = B^-1((1 + c)/2; k + 1, n - k) (1 when
// k = n). Never narrower than its confidence, also at 0 or 100 % and with 2 answers, where the
// normal approximation's interval has zero width. trials > 0.
struct ProportionInterval {
  double low = 0.0;
  double high = 1.0;
};
ProportionInterval clopper_pearson_interval(long successes, long trials, double confidence = 0.95);

// Below this many decided answers (an expected count below 5 with two options, Cochran 1954)
// the chi-square approximation is not reported; the exact binomial test stands alone.
inline constexpr long kChiSquareMinimumAnswers = 10;

// Pearson chi-square goodness of fit of `observed` counts against `expected_proportions`
// (summing to 1; empty means equal proportions, i.e. no preference). df = categories - 1.
TestResult chi_square_goodness_of_fit(const std::vector<long>& observed,
                                      const std::vector<double>& expected_proportions = {});

// Student's paired t-test, two-sided, on pairs (a[i], b[i]); df = n - 1.
TestResult paired_t_test(const std::vector<double>& a, const std::vector<double>& b);

struct MeanSe {
  double mean = 0.0;
  std::optional<double> standard_error;  // empty for fewer than 2 values
  std::size_t n = 0;
};
MeanSe mean_and_standard_error(const std::vector<double>& values);
double median(std::vector<double> values);  // values non-empty
double standard_deviation(const std::vector<double>& values);  // n - 1 denominator; 0 for n < 2

struct RepeatedMeasuresAnova {
  std::string unavailable;
  double f = 0.0;
  double df_condition = 0.0;
  double df_error = 0.0;
  double p_value = 1.0;
  // Greenhouse-Geisser (1959) epsilon from the double-centred covariance matrix of the levels
  // (Box 1954); 1 for two levels. The corrected test uses df * epsilon.
  double epsilon_gg = 1.0;
  double p_value_gg = 1.0;
  std::size_t subjects = 0;
  std::size_t levels = 0;
  bool ok() const { return unavailable.empty(); }
};

// One-way repeated-measures ANOVA: scores[subject][level], complete rows only.
RepeatedMeasuresAnova repeated_measures_anova(const std::vector<std::vector<double>>& scores);

// "p = 0.0123", "p < 0.0001": the form used in the report.
std::string format_p(double p);

}  // namespace glarelab::analysis

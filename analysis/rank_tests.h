#pragma once
// Rank tests for paired ordinal data (ratings): the Wilcoxon signed-rank test for two conditions
// and the Friedman test with Kendall's coefficient of concordance W for several. Definitions
// follow SciPy 1.10 (scipy.stats.wilcoxon, scipy.stats.friedmanchisquare), against which they are
// checked (tests/analysis_rating_scipy_test.cpp). Like analysis/statistics.h, a result either
// carries its numbers or says why there are none (`unavailable`), never NaN.
#include <cstddef>
#include <string>
#include <vector>

namespace glarelab::analysis {

// Ranks 1..n of `values`, ties given the mean of the ranks they span (midranks, as
// scipy.stats.rankdata's default method="average").
std::vector<double> average_ranks(const std::vector<double>& values);

// Sizes of the groups of equal values of size > 1 (the t of the tie corrections).
std::vector<std::size_t> tie_group_sizes(const std::vector<double>& values);

enum class WilcoxonMethod {
  // Exact when at most 50 pairs remain and no difference is zero and no two |differences| are
  // equal; the normal approximation otherwise. SciPy 1.10's "auto" also goes exact with tied
  // |differences| but then truncates the midrank sum to an integer and uses the tie-free
  // distribution; tied ratings are the rule, so the tie-corrected approximation is used instead.
  automatic,
  exact,   // refused (unavailable) when a difference is zero or two |differences| are equal
  normal,  // normal approximation with the tie-corrected variance
};

struct WilcoxonSignedRank {
  std::string unavailable;   // non-empty: why there is no result
  std::size_t pairs = 0;     // pairs given
  std::size_t zero_differences = 0;  // pairs with a == b, discarded (zero_method = "wilcox")
  std::size_t ranked = 0;    // pairs ranked: pairs - zero_differences
  double rank_sum_positive = 0.0;  // R+: sum of the ranks of |a - b| where a > b
  double rank_sum_negative = 0.0;  // R-
  double statistic = 0.0;    // T = min(R+, R-), SciPy's two-sided statistic
  bool exact = false;        // p from the exact null distribution (else the normal approximation)
  bool continuity_correction = false;
  double z = 0.0;            // normal approximation only: (T - n(n+1)/4 - c) / sd
  double p_value = 1.0;      // two-sided
  bool ok() const { return unavailable.empty(); }
};

// Two-sided Wilcoxon (1945) signed-rank test of the paired values (a[i], b[i]). Zero differences
// are discarded before ranking (Wilcoxon's zero_method, SciPy's default "wilcox"); tied |a - b|
// get midranks. Exact: p = 2 min(P(R+ <= r), P(R+ >= r)) under the null distribution of the
// rank sum of n untied ranks (1 when r is the distribution's middle value), at most 1. Normal:
// mean n(n+1)/4, variance n(n+1)(2n+1)/24 - sum(t^3 - t)/48 over tie groups of size t, z = (T -
// mean - c)/sd with c = 0.5 sign(T - mean) when `continuity_correction` (SciPy's default: none).
WilcoxonSignedRank wilcoxon_signed_rank(const std::vector<double>& a, const std::vector<double>& b,
                                        WilcoxonMethod method = WilcoxonMethod::automatic,
                                        bool continuity_correction = false);

struct FriedmanTest {
  std::string unavailable;
  std::size_t subjects = 0;    // n: rows (participants)
  std::size_t conditions = 0;  // k: columns
  double chi_square = 0.0;     // tie-corrected Friedman statistic
  double df = 0.0;             // k - 1
  double p_value = 1.0;        // upper tail of chi-square(k - 1)
  double tie_correction = 1.0; // C = 1 - sum(t^3 - t) / (n k (k^2 - 1)), divides the statistic
  // Kendall's W = chi_square / (n (k - 1)): 0 no agreement between participants on the order of
  // the conditions, 1 complete agreement. Because chi_square is tie-corrected, this is Kendall &
  // Babington Smith's W with the tie correction, 12 S / (n^2 (k^3 - k) - n sum(t^3 - t)).
  double kendall_w = 0.0;
  bool ok() const { return unavailable.empty(); }
};

// Friedman (1937) test on scores[subject][condition], ranked within each subject (midranks for
// ties): chi2 = (12 / (n k (k + 1)) sum_j R_j^2 - 3 n (k + 1)) / C, df = k - 1, as
// scipy.stats.friedmanchisquare. Needs k >= 3 conditions (two: use the signed-rank test), n >= 2
// complete rows, and not every row tied throughout (C = 0).
FriedmanTest friedman_test(const std::vector<std::vector<double>>& scores);

}  // namespace glarelab::analysis

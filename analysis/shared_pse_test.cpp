#include "analysis/shared_pse_test.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/tools/minima.hpp>

namespace glarelab::analysis {
namespace {

constexpr int kGridPoints = 121;
constexpr int kBrentBits = 26;  // half a double's mantissa: Brent's method cannot do better

// ln Phi(z) through erfc, which keeps precision in the lower tail where 1 - Phi(-z) would not.
double log_phi(double z) {
  return std::log(std::max(0.5 * std::erfc(-z / std::sqrt(2.0)), std::numeric_limits<double>::min()));
}

}  // namespace

double cumulative_normal_log_likelihood(const std::vector<StimulusLevel>& levels, double mu, double beta) {
  double sum = 0.0;
  for (const StimulusLevel& level : levels) {
    const double z = beta * (level.intensity - mu);
    const long other = level.trials - level.correct;
    if (level.correct > 0) sum += static_cast<double>(level.correct) * log_phi(z);
    if (other > 0) sum += static_cast<double>(other) * log_phi(-z);
  }
  return sum;
}

namespace {

struct Range {
  double low = 0.0;
  double high = 0.0;
};

Range intensity_range(const std::vector<StimulusLevel>& levels) {
  Range range{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const StimulusLevel& level : levels) {
    range.low = std::min(range.low, level.intensity);
    range.high = std::max(range.high, level.intensity);
  }
  return range;
}

// The slope bounds of the PSE fits (analysis/psychometric_fit.cpp): 1e-3 to 1e3 per tested range.
Range slope_range(const Range& x) {
  const double span = x.high - x.low;
  return {1e-3 / span, 1e3 / span};
}

struct Maximum {
  double mu = 0.0;
  double value = 0.0;
};

// Maximises f over mu on [low, high]: the best of a grid, refined by Brent's method between its
// neighbours.
Maximum maximise_over_mu(const std::function<double(double)>& f, const Range& mu_range) {
  const double step = (mu_range.high - mu_range.low) / (kGridPoints - 1);
  Maximum best{mu_range.low, -std::numeric_limits<double>::infinity()};
  for (int i = 0; i < kGridPoints; ++i) {
    const double mu = mu_range.low + step * i;
    const double value = f(mu);
    if (value > best.value) best = {mu, value};
  }
  const auto [mu, negative] = boost::math::tools::brent_find_minima([&](double m) { return -f(m); },
                                                                    std::max(mu_range.low, best.mu - step),
                                                                    std::min(mu_range.high, best.mu + step), kBrentBits);
  if (-negative > best.value) best = {mu, -negative};
  return best;
}

double profile_with_range(const std::vector<StimulusLevel>& levels, double mu, const Range& slopes, bool* at_bound) {
  // Unimodal in log beta because concave in beta: Brent on the logarithm spans the six decades.
  const auto [log_beta, negative] = boost::math::tools::brent_find_minima(
      [&](double b) { return -cumulative_normal_log_likelihood(levels, mu, std::exp(b)); }, std::log(slopes.low), std::log(slopes.high),
      kBrentBits);
  const double log_span = std::log(slopes.high) - std::log(slopes.low);
  if (at_bound != nullptr) *at_bound = log_beta > std::log(slopes.high) - 1e-3 * log_span;
  return -negative;
}

// Answers that separate perfectly: none for the graded side up to some level, all of them above
// it. Then no finite slope maximises the likelihood.
bool separates(std::vector<StimulusLevel> levels) {
  std::sort(levels.begin(), levels.end(),
            [](const StimulusLevel& a, const StimulusLevel& b) { return a.intensity < b.intensity; });
  for (std::size_t cut = 1; cut < levels.size(); ++cut) {
    bool separated = true;
    for (std::size_t i = 0; i < levels.size() && separated; ++i)
      separated = i < cut ? levels[i].correct == 0 : levels[i].correct == levels[i].trials;
    if (separated) return true;
  }
  return false;
}

}  // namespace

double profile_log_likelihood(const std::vector<StimulusLevel>& levels, double mu, bool* at_bound) {
  return profile_with_range(levels, mu, slope_range(intensity_range(levels)), at_bound);
}

SharedPseTest shared_pse_test(const std::vector<std::vector<StimulusLevel>>& groups) {
  SharedPseTest test;
  if (groups.size() < 2) {
    test.unavailable = "fewer than two groups";
    return test;
  }
  Range all{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  std::vector<Range> slopes;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const Range x = intensity_range(groups[g]);
    long trials = 0, graded = 0;
    for (const StimulusLevel& level : groups[g]) trials += level.trials, graded += level.correct;
    if (groups[g].size() < 2 || graded == 0 || graded == trials) {
      test.unavailable = "group " + std::to_string(g + 1) + " has fewer than two levels or answers all one way";
      return test;
    }
    if (separates(groups[g])) {
      test.unavailable = "the answers of group " + std::to_string(g + 1) + " separate perfectly (no finite slope)";
      return test;
    }
    slopes.push_back(slope_range(x));
    all.low = std::min(all.low, x.low);
    all.high = std::max(all.high, x.high);
  }
  const double span = all.high - all.low;
  const Range mu_range{all.low - span, all.high + span};

  for (std::size_t g = 0; g < groups.size(); ++g) {
    bool steepest = false;
    const Maximum separate =
        maximise_over_mu([&](double mu) { return profile_with_range(groups[g], mu, slopes[g], nullptr); }, mu_range);
    profile_with_range(groups[g], separate.mu, slopes[g], &steepest);
    if (steepest) {
      test.unavailable = "the answers of group " + std::to_string(g + 1) + " separate perfectly (no finite slope)";
      return test;
    }
    test.log_likelihood_separate += separate.value;
  }
  const Maximum shared = maximise_over_mu(
      [&](double mu) {
        double sum = 0.0;
        for (std::size_t g = 0; g < groups.size(); ++g) sum += profile_with_range(groups[g], mu, slopes[g], nullptr);
        return sum;
      },
      mu_range);
  test.log_likelihood_shared = shared.value;
  test.shared_pse = shared.mu;
  // The shared model is nested in the separate one; rounding can leave a tiny negative difference.
  test.statistic = std::max(0.0, 2.0 * (test.log_likelihood_separate - test.log_likelihood_shared));
  test.df = static_cast<int>(groups.size()) - 1;
  test.p_value =
      boost::math::cdf(boost::math::complement(boost::math::chi_squared_distribution<double>(test.df), test.statistic));
  return test;
}

}  // namespace glarelab::analysis

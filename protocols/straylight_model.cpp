#include "protocols/straylight_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>

#include "core/random.h"

namespace glarelab {
namespace {

constexpr double kGridMinLog10 = -0.5;
constexpr double kGridMaxLog10 = 3.0;
constexpr double kGridStepLog10 = 0.005;

double standard_normal_cdf(double z) { return 0.5 * std::erfc(-z / std::numbers::sqrt2); }

}  // namespace

double ring_straylight_constant(double inner_deg, double outer_deg) {
  if (!(inner_deg > 0.0 && outer_deg > inner_deg)) {
    throw std::invalid_argument("ring angles must satisfy 0 < inner < outer degrees");
  }
  constexpr double kRadPerDeg = std::numbers::pi / 180.0;
  return 2.0 * std::numbers::pi * kRadPerDeg * kRadPerDeg * std::log(outer_deg / inner_deg);
}

double straylight_age_norm_log10(double age_years) {
  const double a = age_years / 65.0;
  return 0.87 + std::log10(1.0 + (a * a) * (a * a));
}

double probability_compensated_stronger(double log_s, double log_compensation,
                                        const StraylightPsychometric& psychometric) {
  // Amplitudes in units of k L_ring: s for the plain half, |s - s_c| for the compensated one.
  // Each seen as log10 amplitude plus noise; the compensated half wins when its perceived log
  // amplitude is larger: Phi((log10|s - s_c| - log10 s) / sigma) = Phi(log10|1 - s_c / s| / sigma).
  const double ratio = std::pow(10.0, log_compensation - log_s);
  const double contrast = std::abs(1.0 - ratio);
  const double seen = contrast > 0.0
                          ? standard_normal_cdf(std::log10(contrast) / psychometric.amplitude_noise_log10)
                          : 0.0;
  return 0.5 * psychometric.lapse + (1.0 - psychometric.lapse) * seen;
}

StraylightEstimate estimate_straylight(const std::vector<StraylightAnswer>& answers,
                                       const StraylightPsychometric& psychometric, double display_straylight) {
  if (answers.empty()) throw std::invalid_argument("straylight estimate: no answers");
  StraylightEstimate estimate;
  const int points = static_cast<int>(std::lround((kGridMaxLog10 - kGridMinLog10) / kGridStepLog10)) + 1;
  std::vector<double> log_likelihood(static_cast<std::size_t>(points));
  for (int i = 0; i < points; ++i) {
    const double log_s = kGridMinLog10 + kGridStepLog10 * i;
    const double seen_log_s = display_straylight > 0.0 ? std::log10(std::pow(10.0, log_s) + display_straylight) : log_s;
    double sum = 0.0;
    for (const StraylightAnswer& answer : answers) {
      const double p = probability_compensated_stronger(seen_log_s, answer.log_compensation, psychometric);
      sum += std::log(answer.compensated_stronger ? p : 1.0 - p);
    }
    estimate.likelihood.log_s.push_back(log_s);
    log_likelihood[static_cast<std::size_t>(i)] = sum;
  }
  const auto best = std::max_element(log_likelihood.begin(), log_likelihood.end());
  const double peak = *best;
  const auto best_index = static_cast<std::size_t>(best - log_likelihood.begin());
  estimate.log_s = estimate.likelihood.log_s[best_index];
  // The maximum between grid points: the vertex of the parabola through the best point and its two
  // neighbours (a shift of at most half a grid step).
  if (best_index > 0 && best_index + 1 < log_likelihood.size()) {
    const double left = log_likelihood[best_index - 1];
    const double right = log_likelihood[best_index + 1];
    const double curvature = left - 2.0 * peak + right;
    if (curvature < 0.0) estimate.log_s += 0.5 * kGridStepLog10 * (left - right) / curvature;
  }
  double total = 0.0;
  for (double value : log_likelihood) {
    estimate.likelihood.normalised.push_back(std::exp(value - peak));
    total += estimate.likelihood.normalised.back();
  }
  double mean = 0.0;
  for (std::size_t i = 0; i < log_likelihood.size(); ++i) {
    estimate.likelihood.normalised[i] /= total;
    mean += estimate.likelihood.normalised[i] * estimate.likelihood.log_s[i];
  }
  double variance = 0.0;
  for (std::size_t i = 0; i < log_likelihood.size(); ++i) {
    const double d = estimate.likelihood.log_s[i] - mean;
    variance += estimate.likelihood.normalised[i] * d * d;
  }
  estimate.likelihood_sd_log10 = std::sqrt(variance);
  // The ESD: half the width of the likelihood's peak where it has fallen to e^-1/2 of its maximum
  // (log L = peak - 1/2), each side found by linear interpolation between grid points; a flat side
  // that never falls that far is taken to the grid's end. For a Gaussian likelihood it is its SD;
  // unlike the SD of the whole normalised likelihood it leaves out the far tails, which overstate
  // the scatter of the estimate over repeated measurements (docs/STRAYLIGHT.md, "The estimate").
  const auto crossing = [&](int step) {
    std::size_t i = best_index;
    while (true) {
      if ((step < 0 && i == 0) || (step > 0 && i + 1 == log_likelihood.size())) return estimate.likelihood.log_s[i];
      const std::size_t next = step < 0 ? i - 1 : i + 1;
      if (log_likelihood[next] <= peak - 0.5) {
        const double fraction = (log_likelihood[i] - (peak - 0.5)) / (log_likelihood[i] - log_likelihood[next]);
        return estimate.likelihood.log_s[i] + step * fraction * kGridStepLog10;
      }
      i = next;
    }
  };
  estimate.esd_log10 = 0.5 * (crossing(+1) - crossing(-1));
  // Unreliable when either spread passes the limit: a narrow peak with heavy tails or a second
  // mode (few answers at the fixed levels) scatters like the whole likelihood, not like its peak
  // (docs/STRAYLIGHT.md, "The estimate": 12 answers scatter by 0.09-0.15 with a peak half-width of
  // 0.055-0.066 and a likelihood SD of 0.13).
  estimate.unreliable = std::max(estimate.esd_log10, estimate.likelihood_sd_log10) > kStraylightUnreliableEsdLog10;
  return estimate;
}

double next_log_compensation(const StraylightSchedule& schedule, const std::vector<StraylightAnswer>& answers,
                             const StraylightPsychometric& psychometric, std::uint64_t seed,
                             double display_straylight) {
  const int index = static_cast<int>(answers.size());
  if (index >= schedule.answers) {
    throw std::invalid_argument("straylight schedule: answer " + std::to_string(index + 1) + " of " +
                                std::to_string(schedule.answers) + " asked for");
  }
  if (index < schedule.range_answers) {
    // One-up/one-down from above: a compensated half flickering more means s_c > 2 s, so the next
    // level is lower; starting above any healthy eye keeps the run out of the region s_c < s, where
    // both halves flicker alike and the answers carry little.
    double level = schedule.start_log_compensation;
    for (const StraylightAnswer& answer : answers) {
      level += answer.compensated_stronger ? -schedule.range_step_log10 : schedule.range_step_log10;
    }
    return level;
  }
  // Fixed offsets around 2 s of the estimate from every answer so far (where the halves flicker
  // alike): re-centring on each answer keeps one early lapse from placing all the levels aside.
  const double log_s = estimate_straylight(answers, psychometric, display_straylight).log_s;
  const double centre = display_straylight > 0.0 ? std::log10(2.0 * (std::pow(10.0, log_s) + display_straylight))
                                                 : log_s + std::log10(2.0);
  const int fixed = schedule.answers - schedule.range_answers;
  std::vector<int> order(static_cast<std::size_t>(fixed));
  std::iota(order.begin(), order.end(), 0);
  shuffle_in_place(order, CounterRandom(seed, RandomStream::staircase), 0);
  const int slot = order[static_cast<std::size_t>(index - schedule.range_answers)];
  const double offset =
      fixed > 1 ? schedule.fixed_half_span_log10 * (2.0 * slot / (fixed - 1) - 1.0) : 0.0;
  const double level = centre + offset;
  return schedule.level_step_log10 * std::round(level / schedule.level_step_log10);
}

bool compensation_on_left(std::uint64_t seed, std::uint64_t index) {
  return CounterRandom(seed, RandomStream::trial_order).uniform(index, 7) < 0.5;
}

}  // namespace glarelab

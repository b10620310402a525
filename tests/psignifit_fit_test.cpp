// Psychometric fits as psignifit 4 makes them (analysis/psignifit_fit.h), against psignifit 4's
// own results for its test cases (../shared/data/psignifit-cases, README there; skipped, saying
// so, when the folder is absent), against a brute-force posterior integration written out here
// for the equal-asymptote type (which has no case in that folder), and against closed forms for
// the sigmoids' parameterisation and the credible intervals.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include "analysis/psignifit_fit.h"
#include "analysis/psignifit_io.h"
#include "analysis/psignifit_posterior.h"
#include "analysis/psignifit_sigmoid.h"
#include "core/errors.h"

namespace glarelab::analysis {
namespace {

using nlohmann::json;

// The shared data folder beside the repository; GLARELAB_SHARED_DIR names another place for it.
std::filesystem::path psignifit_cases_dir() {
  if (const char* shared = std::getenv("GLARELAB_SHARED_DIR"); shared != nullptr && *shared != '\0')
    return std::filesystem::path(shared) / "data" / "psignifit-cases";
  return std::filesystem::path(GLARELAB_SOURCE_DIR) / ".." / "shared" / "data" / "psignifit-cases";
}

std::vector<std::string> psignifit_case_names(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string file = entry.path().filename().string();
    const std::string suffix = "_opt.json";
    if (file.size() > suffix.size() && file.ends_with(suffix)) names.push_back(file.substr(0, file.size() - suffix.size()));
  }
  std::sort(names.begin(), names.end());
  return names;
}

json read_json(const std::filesystem::path& path) {
  std::ifstream in(path);
  return json::parse(in);
}

bool expected_is_number(double value) { return std::isfinite(value); }

// Acceptance 1 of the fits: threshold and width (MAP and mean) within 1 % of the stimulus range
// on the fitted axis, lambda, gamma and eta within 0.01; the credible intervals' ends within 2 %
// of the range for threshold and width, 0.02 for the others; the deviance within 1 %. Returns
// the largest deviation in units of its tolerance.
double expect_agrees(const std::string& name, const PsignifitResult& mine, const json& reference) {
  const double range = mine.fitted_range[1] - mine.fitted_range[0];
  double worst = 0.0;
  const auto check = [&](const std::string& what, double value, double expected, double tolerance) {
    if (!expected_is_number(expected)) return;
    EXPECT_NEAR(value, expected, tolerance) << name << ": " << what;
    worst = std::max(worst, std::abs(value - expected) / tolerance);
  };
  for (int p = 0; p < kPsignifitParameters; ++p) {
    const double point_tolerance = p < 2 ? 0.01 * range : 0.01;
    const double interval_tolerance = p < 2 ? 0.02 * range : 0.02;
    check("Fit[" + std::to_string(p) + "]", mine.fit[p], reference["Fit"][p].get<double>(), point_tolerance);
    check("meanFit[" + std::to_string(p) + "]", mine.mean_fit[p], reference["meanFit"][p].get<double>(), point_tolerance);
    for (int level = 0; level < 3; ++level) {
      const std::string which = "conf_Intervals[" + std::to_string(p) + "] at " + std::to_string(level);
      check(which + " low", mine.intervals[p][level].low, reference["conf_Intervals"][p][0][level].get<double>(), interval_tolerance);
      check(which + " high", mine.intervals[p][level].high, reference["conf_Intervals"][p][1][level].get<double>(), interval_tolerance);
    }
  }
  const double deviance = reference["deviance"].get<double>();
  check("deviance", mine.deviance, deviance, 0.01 * deviance);
  return worst;
}

PsignifitOptions case_options(const std::filesystem::path& dir, const std::string& name) {
  return read_psignifit_options((dir / (name + "_opt.json")).string());
}

TEST(PsignifitCases, EveryCaseAgreesWithPsignifit4) {
  const auto dir = psignifit_cases_dir();
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " is not present (psignifit 4's reference cases, ../shared/data)";
  const std::vector<std::string> names = psignifit_case_names(dir);
  ASSERT_GE(names.size(), 16u) << "the README lists 16 cases";
  const auto start = std::chrono::steady_clock::now();
  double worst = 0.0;
  for (const std::string& name : names) {
    const auto data = read_psignifit_data((dir / (name + "_data.csv")).string());
    const PsignifitResult result = psignifit_fit(data, case_options(dir, name));
    const json reference = read_json(dir / (name + "_res.json"));
    const double case_worst = expect_agrees(name, result, reference);
    worst = std::max(worst, case_worst);
    // The grid is psignifit's: the same pooled blocks and the same moved borders.
    ASSERT_EQ(result.blocks.size(), reference["data"].size()) << name;
    for (std::size_t b = 0; b < result.blocks.size(); ++b) {
      EXPECT_NEAR(result.blocks[b].level, reference["data"][b][0].get<double>(), 1e-12) << name;
      EXPECT_EQ(result.blocks[b].correct, reference["data"][b][1].get<long>()) << name;
      EXPECT_EQ(result.blocks[b].trials, reference["data"][b][2].get<long>()) << name;
    }
    for (int p = 0; p < kPsignifitParameters; ++p) {
      const json& axis = reference["X1D"][p];
      const double first = axis.is_array() ? axis.front().get<double>() : axis.get<double>();
      const double last = axis.is_array() ? axis.back().get<double>() : axis.get<double>();
      EXPECT_NEAR(result.grid[p].front(), first, 1e-9) << name << " grid of parameter " << p;
      EXPECT_NEAR(result.grid[p].back(), last, 1e-9) << name << " grid of parameter " << p;
    }
    EXPECT_NEAR(result.log_p_max, reference["logPmax"].get<double>(), 1e-6) << name;
    std::cout << "  " << name << ": largest deviation " << case_worst << " of its tolerance\n";
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "  " << names.size() << " cases in " << seconds << " s; largest deviation " << worst << " of its tolerance\n";
}

// The equal-asymptote posterior (lambda = gamma) integrated by brute force on a fine midpoint
// grid over the whole prior support, with the likelihood, sigmoid and priors written out here
// from the paper's definitions (Schuett et al. 2016, Eq. 1 and section 2.4), eta fixed at 0.
TEST(PsignifitFit, EqualAsymptoteAgreesWithBruteForcePosterior) {
  // Ten levels, 20 trials each, answers rounded from a known observer.
  std::vector<PsignifitBlock> data;
  const double sigma_per_width = 1.0 / (2.0 * 1.6448536269514722);  // norm: w spans 5 % to 95 %
  for (int i = 0; i < 10; ++i) {
    const double level = 0.25 + i / 6.0;
    const double f = 0.5 * std::erfc(-(level - 1.0) / (0.8 * sigma_per_width) / std::numbers::sqrt2);
    const double psi = 0.08 + (1.0 - 0.16) * f;
    data.push_back({level, std::lround(20.0 * psi), 20});
  }
  PsignifitOptions options;
  options.experiment = PsignifitExperiment::equal_asymptote;
  options.fixed[4] = 0.0;
  const PsignifitResult result = psignifit_fit(data, options);

  const double low = 0.25, high = 1.75, spread = high - low, width_min = 1.0 / 6.0;
  const auto threshold_prior = [&](double m) {
    if (m < low) return 0.5 + 0.5 * std::cos(2.0 * std::numbers::pi * (low - m) / spread);
    if (m > high) return 0.5 + 0.5 * std::cos(2.0 * std::numbers::pi * (m - high) / spread);
    return 1.0;
  };
  const auto width_prior = [&](double w) {
    if (w <= 2.0 * width_min) return 0.5 - 0.5 * std::cos(std::numbers::pi * (w - width_min) / width_min);
    if (w >= spread) return 0.5 + 0.5 * std::cos(0.5 * std::numbers::pi * (w - spread) / spread);
    return 1.0;
  };
  const int nm = 150, nw = 150, nl = 80;
  const double m0 = low - 0.5 * spread, m1 = high + 0.5 * spread, w0 = width_min, w1 = 3.0 * spread, l0 = 0.0, l1 = 0.5;
  std::vector<double> mass_m(nm, 0.0), mass_w(nw, 0.0), mass_l(nl, 0.0);
  std::vector<double> log_post(static_cast<std::size_t>(nm) * nw * nl);
  double best = -1e300;
  for (int a = 0; a < nm; ++a)
    for (int b = 0; b < nw; ++b)
      for (int c = 0; c < nl; ++c) {
        const double m = m0 + (a + 0.5) * (m1 - m0) / nm, w = w0 + (b + 0.5) * (w1 - w0) / nw, lambda = l0 + (c + 0.5) * (l1 - l0) / nl;
        double value = std::log(threshold_prior(m)) + std::log(width_prior(w)) + std::log(10.0 * std::pow(1.0 - lambda, 9.0));
        for (const PsignifitBlock& block : data) {
          const double f = 0.5 * std::erfc(-(block.level - m) / (w * sigma_per_width) / std::numbers::sqrt2);
          const double psi = lambda + (1.0 - 2.0 * lambda) * f;
          value += static_cast<double>(block.correct) * std::log(psi) +
                   static_cast<double>(block.trials - block.correct) * std::log(1.0 - psi);
        }
        log_post[(static_cast<std::size_t>(a) * nw + b) * nl + c] = value;
        best = std::max(best, value);
      }
  for (int a = 0; a < nm; ++a)
    for (int b = 0; b < nw; ++b)
      for (int c = 0; c < nl; ++c) {
        const double p = std::exp(log_post[(static_cast<std::size_t>(a) * nw + b) * nl + c] - best);
        mass_m[a] += p;
        mass_w[b] += p;
        mass_l[c] += p;
      }
  // Mean and central interval of a marginal on cells of equal width.
  const auto summary = [](const std::vector<double>& mass, double start, double stop, double p) {
    double total = 0.0, mean = 0.0;
    const double cell = (stop - start) / static_cast<double>(mass.size());
    for (std::size_t i = 0; i < mass.size(); ++i) {
      total += mass[i];
      mean += mass[i] * (start + (static_cast<double>(i) + 0.5) * cell);
    }
    const auto quantile = [&](double q) {
      double cumulative = 0.0;
      for (std::size_t i = 0; i < mass.size(); ++i) {
        if (cumulative + mass[i] / total >= q) return start + (static_cast<double>(i) + (q - cumulative) / (mass[i] / total)) * cell;
        cumulative += mass[i] / total;
      }
      return stop;
    };
    return std::array<double, 3>{mean / total, quantile(0.5 * (1.0 - p)), quantile(0.5 * (1.0 + p))};
  };
  const auto threshold = summary(mass_m, m0, m1, 0.95), width = summary(mass_w, w0, w1, 0.95), lambda = summary(mass_l, l0, l1, 0.95);
  std::cout << "  brute force: threshold " << threshold[0] << " width " << width[0] << " lambda " << lambda[0] << "; fit "
            << result.mean_fit[0] << " " << result.mean_fit[1] << " " << result.mean_fit[2] << "\n";
  EXPECT_NEAR(result.mean_fit[0], threshold[0], 0.01 * spread);
  EXPECT_NEAR(result.mean_fit[1], width[0], 0.01 * spread);
  EXPECT_NEAR(result.mean_fit[2], lambda[0], 0.01);
  EXPECT_NEAR(result.intervals[0][0].low, threshold[1], 0.02 * spread);
  EXPECT_NEAR(result.intervals[0][0].high, threshold[2], 0.02 * spread);
  EXPECT_NEAR(result.intervals[1][0].low, width[1], 0.02 * spread);
  EXPECT_NEAR(result.intervals[1][0].high, width[2], 0.02 * spread);
  EXPECT_NEAR(result.intervals[2][0].low, lambda[1], 0.02);
  EXPECT_NEAR(result.intervals[2][0].high, lambda[2], 0.02);
  // The two asymptotes are one parameter.
  EXPECT_EQ(result.fit[3], result.fit[2]);
  EXPECT_EQ(result.mean_fit[3], result.mean_fit[2]);
  EXPECT_EQ(result.fit[4], 0.0);
  // The MAP is near the true observer it was rounded from.
  EXPECT_NEAR(result.map[0], 1.0, 0.1);
  EXPECT_NEAR(result.map[2], 0.08, 0.05);
}

// F(m) = PC and F^-1(1 - alpha) - F^-1(alpha) = w for every sigmoid (paper section 2.1), with the
// alpha and 1 - alpha points found by bisection on F itself.
TEST(PsignifitSigmoid, ThresholdAndWidthMeanWhatThePaperSays) {
  for (PsignifitSigmoid sigmoid : {PsignifitSigmoid::norm, PsignifitSigmoid::logistic, PsignifitSigmoid::gumbel,
                                   PsignifitSigmoid::rgumbel, PsignifitSigmoid::tdist, PsignifitSigmoid::weibull,
                                   PsignifitSigmoid::logn}) {
    for (double pc : {0.5, 0.75}) {
      for (double alpha : {0.05, 0.1}) {
        const PsignifitSigmoidCurve curve(sigmoid, pc, alpha);
        const double m = 0.3, w = 1.7;
        EXPECT_NEAR(curve(m, m, w), pc, 1e-12) << psignifit_sigmoid_name(sigmoid);
        const auto solve = [&](double target) {
          double a = m - 1e3, b = m + 1e3;
          for (int i = 0; i < 200; ++i) (curve(0.5 * (a + b), m, w) < target ? a : b) = 0.5 * (a + b);
          return 0.5 * (a + b);
        };
        EXPECT_NEAR(solve(1.0 - alpha) - solve(alpha), w, 1e-9) << psignifit_sigmoid_name(sigmoid) << " pc " << pc;
        EXPECT_NEAR(curve.inverse(0.9, m, w), solve(0.9), 1e-9) << psignifit_sigmoid_name(sigmoid);
        // The derivative against a central difference.
        const double h = 1e-6;
        EXPECT_NEAR(curve.derivative(m + 0.2, m, w), (curve(m + 0.2 + h, m, w) - curve(m + 0.2 - h, m, w)) / (2 * h), 1e-6);
      }
    }
  }
  // Closed form: the normal with PC 0.5 and alpha 0.05 reaches 0.95 half a width above threshold.
  EXPECT_NEAR(PsignifitSigmoidCurve(PsignifitSigmoid::norm, 0.5, 0.05)(1.5, 1.0, 1.0), 0.95, 1e-12);
}

// The beta-binomial likelihood (paper Eq. 4-5) against log-gamma written out here, for blocks
// small enough for the grid's plain products and large enough (500 trials) for the checked ones;
// the grid's posterior ratios against the point evaluation.
TEST(PsignifitPosterior, BetaBinomialAgreesWithLogGamma) {
  for (long trials : {10L, 500L}) {
    std::vector<PsignifitBlock> blocks;
    for (int i = 0; i < 6; ++i) blocks.push_back({0.2 * i, trials * (i + 1) / 7, trials});
    PsignifitModel model{PsignifitSigmoidCurve(PsignifitSigmoid::logistic, 0.5, 0.05), PsignifitExperiment::yes_no, blocks, {}};
    model.prior.range_low = 0.0;
    model.prior.range_high = 1.0;
    model.prior.width_min = 0.2;
    model.prior.normalise({{{-0.5, 1.5}, {0.2, 3.0}, {0.0, 0.5}, {0.0, 0.5}, {0.0, 1.0}}});
    const auto log_likelihood = [&](const PsignifitParameters& t) {
      const double v = 1.0 / (t[4] * t[4]) - 1.0;
      double sum = 0.0;
      for (const PsignifitBlock& block : blocks) {
        const double f = 1.0 / (1.0 + std::exp(-2.0 * std::log(19.0) / t[1] * (block.level - t[0])));
        const double psi = t[3] + (1.0 - t[3] - t[2]) * f;
        const double k = static_cast<double>(block.correct), n = static_cast<double>(block.trials);
        const double a = psi * v, b = (1.0 - psi) * v;
        sum += std::lgamma(k + a) + std::lgamma(n - k + b) - std::lgamma(n + v) - std::lgamma(a) - std::lgamma(b) + std::lgamma(v);
      }
      return sum;
    };
    // Two thresholds inside the flat part of the threshold prior: the priors cancel.
    const PsignifitParameters first{0.4, 1.0, 0.03, 0.05, 0.3}, second{0.6, 1.0, 0.03, 0.05, 0.3};
    EXPECT_NEAR(psignifit_log_posterior(model, first) - psignifit_log_posterior(model, second),
                log_likelihood(first) - log_likelihood(second), 1e-8 * std::max(1.0, std::abs(log_likelihood(first))))
        << trials << " trials per block";
    // The grid at two nodes against the point evaluation.
    PsignifitAxes axes = {std::vector<double>{0.4, 0.6}, {1.0}, {0.03}, {0.05}, {0.3}};
    const PsignifitGrid grid = psignifit_grid(model, axes);
    EXPECT_NEAR(std::log(grid.posterior[0] / grid.posterior[1]),
                psignifit_log_posterior(model, first) - psignifit_log_posterior(model, second), 1e-8 * std::max(1.0, std::abs(log_likelihood(first))))
        << trials << " trials per block";
  }
}

// A uniform marginal on [0, 1]: its central 95 % interval is [0.025, 0.975].
TEST(PsignifitPosterior, PercentileIntervalOfAUniformMarginalIsItsQuantiles) {
  std::vector<double> axis, marginal(11, 1.0);
  for (int i = 0; i <= 10; ++i) axis.push_back(i / 10.0);
  const auto weights = psignifit_axis_weights(axis);
  for (double p : {0.95, 0.9, 0.68}) {
    const PsignifitInterval interval = psignifit_percentile_interval(marginal, axis, weights, p);
    EXPECT_NEAR(interval.low, 0.5 * (1.0 - p), 1e-12);
    EXPECT_NEAR(interval.high, 0.5 * (1.0 + p), 1e-12);
  }
}

TEST(PsignifitFit, FixedParametersStayFixed) {
  std::vector<PsignifitBlock> data;
  for (int i = 0; i < 8; ++i) data.push_back({1.0 + i, 10 + 2 * i, 30});
  PsignifitOptions options;
  options.experiment = PsignifitExperiment::n_afc;
  options.alternatives = 3;
  options.fixed[2] = 0.02;
  options.fixed[4] = 0.0;
  options.grid_steps = std::array<int, kPsignifitParameters>{30, 30, 1, 1, 1};
  const PsignifitResult result = psignifit_fit(data, options);
  EXPECT_EQ(result.fit[2], 0.02);
  EXPECT_EQ(result.fit[4], 0.0);
  EXPECT_NEAR(result.fit[3], 1.0 / 3.0, 1e-15);
  EXPECT_EQ(result.intervals[2][0].low, 0.02);
  EXPECT_EQ(result.intervals[2][0].high, 0.02);
  // psi at the threshold is gamma + (1 - gamma - lambda) PC.
  EXPECT_NEAR(psignifit_psi(result.options, result.fit, result.fit[0]), 1.0 / 3.0 + (1.0 - 1.0 / 3.0 - 0.02) * 0.5, 1e-12);
  EXPECT_NEAR(psignifit_threshold(result.options, result.fit, 0.5), result.fit[0], 1e-12);
}

TEST(PsignifitIo, ErrorsNameFileLineAndKey) {
  try {
    parse_psignifit_options("{\n  \"expType\": \"2AFC\",\n  \"sigmoid\": \"norm\"\n}\n", "opt.json");
    FAIL() << "an unknown option name was accepted";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.where().line, 3);
    EXPECT_EQ(error.where().column, 3);
    EXPECT_EQ(error.key(), "sigmoid");
    EXPECT_NE(std::string(error.what()).find("opt.json:3:3"), std::string::npos) << error.what();
  }
  try {
    parse_psignifit_options("{\"threshPC\": 1.5}", "opt.json");
    FAIL() << "threshPC 1.5 was accepted";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.key(), "threshPC");
  }
  try {
    parse_psignifit_options("{\"expType\": \"2AFC\",,}", "opt.json");
    FAIL() << "broken JSON was accepted";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.where().line, 1);
  }
  try {
    parse_psignifit_data("0.5,3,10\n0.7,x,10\n", "data.csv");
    FAIL() << "a bad count was accepted";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.where().line, 2);
    EXPECT_EQ(error.key(), "correct");
  }
  EXPECT_THROW(parse_psignifit_data("0.5,11,10\n", "data.csv"), ConfigError);
  const auto blocks = parse_psignifit_data("level,correct,trials\n0.5, 3, 10\n\n# note\n0.7,4,10\n", "data.csv");
  ASSERT_EQ(blocks.size(), 2u);
  EXPECT_EQ(blocks[1].correct, 4);
  const PsignifitOptions options = parse_psignifit_options(
      "{\"expType\":\"YesNo\",\"sigmoidName\":\"Weibull\",\"fixedPars\":[null,null,0.01,null,null],\"poolMaxGap\":null,\"confP\":0.9}", "o");
  EXPECT_EQ(options.sigmoid, PsignifitSigmoid::weibull);
  EXPECT_EQ(options.fixed[2], 0.01);
  EXPECT_TRUE(std::isinf(options.pool_max_gap));
  EXPECT_EQ(options.credibility, std::vector<double>{0.9});
}

// Pooling: blocks within poolxTol of a block's level join it, weighted by trials (psignifit's poolData).
TEST(PsignifitFit, PoolingJoinsBlocksWithinTolerance) {
  PsignifitOptions options;
  options.pool_x_tol = 0.05;
  const std::vector<PsignifitBlock> data = {{1.0, 1, 1}, {2.0, 0, 1}, {1.04, 1, 3}, {2.03, 1, 1}, {1.2, 0, 1}};
  const auto pooled = psignifit_pool(data, options);
  ASSERT_EQ(pooled.size(), 3u);
  EXPECT_NEAR(pooled[0].level, (1.0 + 3 * 1.04) / 4.0, 1e-15);
  EXPECT_EQ(pooled[0].correct, 2);
  EXPECT_EQ(pooled[0].trials, 4);
  EXPECT_NEAR(pooled[1].level, 2.015, 1e-15);
  EXPECT_EQ(pooled[2].trials, 1);
  options.pool_max_gap = 0.0;  // no trial of another level may come between
  EXPECT_EQ(psignifit_pool(data, options).size(), 5u);
}

}  // namespace
}  // namespace glarelab::analysis

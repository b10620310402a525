// A within-participant glare study analysed as one (analysis/within_participant.h): simulated
// participants, each with a known PSE of their own in each glare mode, answer a two-sided
// graded forced choice whose trials go straight into the analysis as `analyze` loads them.
//
// The population: participant p's control PSE is N(0, 0.06^2) and their static-glare shift
// N(0.10, 0.04^2) (log10 luminance ratio); the observer names scene_b with probability
// Phi((x - PSE_p,mode) / 0.10) (a cumulative normal of the same family the fit uses). Every draw
// comes from the project's counter-based generator (core/random.h, stream `observer`). The group
// truth is the population's mean shift, 0.10, which the summary-statistics t interval targets.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <boost/math/distributions/students_t.hpp>

#include "analysis/graded_choice_analysis.h"
#include "analysis/loaded_database.h"
#include "analysis/psignifit_pse.h"
#include "core/random.h"

namespace glarelab::analysis {
namespace {

constexpr double kSigma = 0.10;            // the observers' noise (log10 units)
constexpr double kMeanShift = 0.10;        // the population's static-glare shift
constexpr double kShiftSd = 0.04;
constexpr double kControlSd = 0.06;
constexpr int kTrialsPerLevel = 6;         // per participant, mode and level (3 per side)

struct Truth {
  std::vector<double> control_pse;
  std::vector<double> static_pse;
};

// The tested levels, log10 luminance ratio -0.30 to 0.40 in steps of 0.10.
std::vector<double> levels() {
  std::vector<double> x;
  for (int i = -3; i <= 4; ++i) x.push_back(0.1 * i);
  return x;
}

LoadedTrial trial(const std::string& glare, double x, bool b_on_left, bool b_named) {
  LoadedTrial t;
  t.record.procedure = "forced_choice";
  t.record.response = b_named == b_on_left ? "left" : "right";
  char ratio[40];
  std::snprintf(ratio, sizeof ratio, "%.17g", std::pow(10.0, x));
  t.condition = {{"scene_a", "reference"},
                 {"scene_b", "comparison"},
                 {"left", b_on_left ? "comparison" : "reference"},
                 {"right", b_on_left ? "reference" : "comparison"},
                 {"glare", glare},
                 {"luminance_ratio", ratio}};
  return t;
}

// One session per participant, both glare modes interleaved as one session would run them.
LoadedData simulate(std::uint64_t seed, int participants, Truth& truth) {
  const CounterRandom random(seed, RandomStream::observer);
  LoadedData data;
  std::uint64_t counter = 0;
  for (int p = 0; p < participants; ++p) {
    const double control = kControlSd * random.normal(counter++);
    const double shift = kMeanShift + kShiftSd * random.normal(counter++);
    truth.control_pse.push_back(control);
    truth.static_pse.push_back(control + shift);
    LoadedSession session;
    session.record.id = p + 1;
    session.record.participant = "P" + std::to_string(p + 1);
    session.label = session.record.participant + " (db#" + std::to_string(p + 1) + ")";
    for (double x : levels())
      for (int k = 0; k < kTrialsPerLevel; ++k)
        for (const char* mode : {"control", "static"}) {
          const double pse = std::string(mode) == "control" ? control : control + shift;
          const double p_b = 0.5 * std::erfc(-(x - pse) / kSigma / std::sqrt(2.0));
          session.trials.push_back(trial(mode, x, k % 2 == 0, random.uniform(counter++) < p_b));
        }
    data.sessions.push_back(std::move(session));
  }
  return data;
}

GradedChoiceOptions quick() {
  GradedChoiceOptions options;
  options.bootstrap_samples = 0;  // the pooled ML fit's bootstrap is not under test here
  return options;
}

// Acceptance: 8 participants, 40 seeds. The group shift's 95 % interval holds the population's
// mean shift in 36 to 40 runs; the per-participant PSEs' 95 % intervals hold each participant's
// own PSE in at least 90 % of the 640.
TEST(AnalysisWithinParticipant, EightParticipantsCoverTheTruth) {
  int group_inside = 0, pse_inside = 0, pse_total = 0, shift_inside = 0, shift_total = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    Truth truth;
    const GradedChoiceAnalysis analysis = analyse_graded_choice(simulate(seed, 8, truth), quick());
    const WithinParticipantAnalysis& within = analysis.within;
    ASSERT_TRUE(within.within);
    ASSERT_EQ(within.participants.size(), 8u);
    ASSERT_EQ(within.baseline, "control");
    ASSERT_EQ(within.cells.size(), 16u);
    for (const ParticipantCell& cell : within.cells) {
      const std::size_t p = static_cast<std::size_t>(std::stoi(cell.participant.substr(1)) - 1);
      ASSERT_TRUE(cell.fit) << cell.participant << " " << cell.group;
      const double pse = cell.group == "control" ? truth.control_pse[p] : truth.static_pse[p];
      ++pse_total;
      pse_inside += cell.fit->credible.low <= pse && pse <= cell.fit->credible.high ? 1 : 0;
      EXPECT_LT(cell.fit->credible.low, cell.fit->credible.high);
      if (cell.group == "static") {
        ASSERT_TRUE(cell.shift_interval);
        const double shift = truth.static_pse[p] - truth.control_pse[p];
        ++shift_total;
        shift_inside += cell.shift_interval->low <= shift && shift <= cell.shift_interval->high ? 1 : 0;
      }
    }
    ASSERT_EQ(within.effects.size(), 1u);
    const WithinParticipantEffect& effect = within.effects.front();
    ASSERT_EQ(effect.participants.size(), 8u);
    ASSERT_TRUE(effect.interval) << effect.paired_t.unavailable;
    ASSERT_TRUE(effect.wilcoxon.ok()) << effect.wilcoxon.unavailable;
    group_inside += effect.interval->low <= kMeanShift && kMeanShift <= effect.interval->high ? 1 : 0;
    EXPECT_EQ(analysis.sessions.size(), 8u);
  }
  std::printf("group shift inside in %d of 40; participant PSEs inside in %d of %d; participant shifts in %d of %d\n",
              group_inside, pse_inside, pse_total, shift_inside, shift_total);
  EXPECT_GE(group_inside, 36);
  EXPECT_GE(pse_inside, static_cast<int>(std::ceil(0.9 * pse_total)));
  EXPECT_GE(shift_inside, static_cast<int>(std::ceil(0.9 * shift_total)));
}

// The group interval is the t interval of the shifts; written out here from the shifts with the
// t quantile and checked against the paired t test's own statistic: t = mean / (sd / sqrt(n)),
// so the half-width is mean t(0.975, n - 1) / t.
TEST(AnalysisWithinParticipant, GroupIntervalIsTheTIntervalOfTheShifts) {
  Truth truth;
  const GradedChoiceAnalysis analysis = analyse_graded_choice(simulate(7, 5, truth), quick());
  ASSERT_EQ(analysis.within.effects.size(), 1u);
  const WithinParticipantEffect& effect = analysis.within.effects.front();
  ASSERT_EQ(effect.shifts.size(), 5u);
  double mean = 0.0;
  for (double s : effect.shifts) mean += s / 5.0;
  double squares = 0.0;
  for (double s : effect.shifts) squares += (s - mean) * (s - mean);
  const double t_crit = boost::math::quantile(boost::math::students_t_distribution<double>(4.0), 0.975);
  const double half = t_crit * std::sqrt(squares / 4.0) / std::sqrt(5.0);
  ASSERT_TRUE(effect.interval);
  EXPECT_NEAR(effect.mean_shift, mean, 1e-12);
  EXPECT_NEAR(effect.interval->low, mean - half, 1e-12);
  EXPECT_NEAR(effect.interval->high, mean + half, 1e-12);
  ASSERT_TRUE(effect.paired_t.ok());
  EXPECT_NEAR(std::abs(mean) * t_crit / std::abs(effect.paired_t.statistic), half, 1e-9);
  // Five participants: the signed-rank test could not reach p = 0.05 (2 / 2^5 = 0.0625), not run.
  EXPECT_FALSE(effect.wilcoxon.ok());
  EXPECT_NE(effect.wilcoxon.unavailable.find("0.0625"), std::string::npos) << effect.wilcoxon.unavailable;
}

// One participant: every per-participant fit and shift, but no test across participants, and
// each reason says so (no signed-rank test "on 1 participant").
TEST(AnalysisWithinParticipant, OneParticipantRunsNoGroupTest) {
  Truth truth;
  const GradedChoiceAnalysis analysis = analyse_graded_choice(simulate(3, 1, truth), quick());
  const WithinParticipantAnalysis& within = analysis.within;
  ASSERT_TRUE(within.within);
  ASSERT_EQ(within.cells.size(), 2u);
  ASSERT_TRUE(within.cells[1].shift_interval);
  ASSERT_EQ(within.effects.size(), 1u);
  EXPECT_FALSE(within.effects[0].interval);
  EXPECT_FALSE(within.effects[0].paired_t.ok());
  EXPECT_NE(within.effects[0].paired_t.unavailable.find("needs at least 2"), std::string::npos);
  EXPECT_FALSE(within.effects[0].wilcoxon.ok());
}

// Each participant answering one glare mode only: the factor is between participants, so no
// paired effect is formed.
TEST(AnalysisWithinParticipant, BetweenParticipantsFormsNoPairs) {
  Truth truth;
  LoadedData data = simulate(5, 4, truth);
  for (std::size_t s = 0; s < data.sessions.size(); ++s) {
    auto& trials = data.sessions[s].trials;
    const std::string keep = s % 2 == 0 ? "control" : "static";
    std::erase_if(trials, [&](const LoadedTrial& t) { return *t.condition_value("glare") != keep; });
  }
  const GradedChoiceAnalysis analysis = analyse_graded_choice(data, quick());
  EXPECT_FALSE(analysis.within.within);
  EXPECT_TRUE(analysis.within.effects.empty());
  EXPECT_EQ(analysis.within.cells.size(), 4u);
}

// The difference interval of two threshold marginals against a second computation: every cell's
// mass split over 40 equal sub-points, every pair of sub-points taken, the central 95 % read off
// the sorted differences. The two agree to a fraction of a grid cell.
TEST(AnalysisWithinParticipant, DifferenceIntervalMatchesDiscretisedConvolution) {
  const std::vector<StimulusLevel> a = {{-0.2, 6, 0}, {-0.1, 6, 1}, {0.0, 6, 3}, {0.1, 6, 5}, {0.2, 6, 6}};
  const std::vector<StimulusLevel> b = {{-0.2, 6, 0}, {-0.1, 6, 0}, {0.0, 6, 1}, {0.1, 6, 3}, {0.2, 6, 5}};
  const auto fit_a = psignifit_pse(a);
  const auto fit_b = psignifit_pse(b);
  ASSERT_TRUE(fit_a && fit_b);
  const auto points = [](const PsignifitPse& fit) {
    const PsignifitResult& r = fit.result;
    std::vector<std::pair<double, double>> out;
    const double step = r.grid[0][1] - r.grid[0][0];
    double total = 0.0;
    for (std::size_t i = 0; i < r.grid[0].size(); ++i) total += r.marginals[0][i] * r.marginal_weights[0][i];
    constexpr int kSub = 40;
    for (std::size_t i = 0; i < r.grid[0].size(); ++i)
      for (int k = 0; k < kSub; ++k)
        out.emplace_back(r.grid[0][i] - 0.5 * step + step * (k + 0.5) / kSub,
                         r.marginals[0][i] * r.marginal_weights[0][i] / total / kSub);
    return out;
  };
  const auto pa = points(*fit_a), pb = points(*fit_b);
  std::vector<std::pair<double, double>> differences;
  for (const auto& [xa, ma] : pa)
    for (const auto& [xb, mb] : pb)
      if (ma * mb > 1e-14) differences.emplace_back(xb - xa, ma * mb);
  std::sort(differences.begin(), differences.end());
  double total = 0.0;
  for (const auto& d : differences) total += d.second;
  const auto quantile = [&](double q) {
    double below = 0.0;
    for (const auto& [x, m] : differences) {
      below += m;
      if (below >= q * total) return x;
    }
    return differences.back().first;
  };
  const Interval interval = psignifit_pse_difference_interval(*fit_a, *fit_b);
  const double cell = std::max(fit_a->result.grid[0][1] - fit_a->result.grid[0][0], fit_b->result.grid[0][1] - fit_b->result.grid[0][0]);
  EXPECT_NEAR(interval.low, quantile(0.025), 0.05 * cell);
  EXPECT_NEAR(interval.high, quantile(0.975), 0.05 * cell);
  EXPECT_GT(interval.low, 0.0);  // b's PSE lies about 0.1 above a's
}

}  // namespace
}  // namespace glarelab::analysis

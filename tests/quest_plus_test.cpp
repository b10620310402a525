// QUEST+ (protocols/quest_plus.h) against the published examples of Watson 2017 as the questplus
// package's test suite holds them, every chosen stimulus compared, and against closed forms.
//
// Reference: hoechenberger/questplus, questplus/tests/test_qp.py at commit
// c50ef73034ad476ffdb7516c2dc0253c3730d0db (the vectors are identical at 15e63bf18fbd3e9a370dadf0ceba8e0ebc354c04):
// test_threshold, test_threshold_slope, test_threshold_slope_lapse, test_mean_sd_lapse and
// test_spatial_contrast_sensitivity. Each gives the grids, the fixed response sequence and the
// stimulus QUEST+ must choose before every response; responses are written C (correct) and
// I (incorrect). Grids written with np.arange over fractions are rebuilt the way numpy builds
// them (numpy_arange below), so grid values agree to the bit.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "protocols/quest_plus.h"

namespace glarelab {
namespace {

// numpy.arange(start, stop, step) for floats: ceil((stop - start) / step) values
// start + i * delta with delta = (start + step) - start.
std::vector<double> numpy_arange(double start, double stop, double step) {
  const auto n = static_cast<std::size_t>(std::ceil((stop - start) / step));
  const double delta = (start + step) - start;
  std::vector<double> values;
  for (std::size_t i = 0; i < n; ++i) values.push_back(start + static_cast<double>(i) * delta);
  return values;
}

std::vector<double> integers(int from, int to, int step = 1) {
  std::vector<double> values;
  for (int v = from; v <= to; v += step) values.push_back(v);
  return values;
}

ParameterAxis axis(std::string name, ParameterRole role, std::vector<double> values, std::size_t dimension = 0) {
  ParameterAxis a;
  a.name = std::move(name);
  a.role = role;
  a.values = std::move(values);
  a.stimulus_dimension = dimension;
  return a;
}

// Runs the fixed responses and checks the stimulus chosen before each (first dimension, and
// the second when `second` is given).
void expect_sequence(QuestPlus& q, const std::vector<int>& first, const char* responses,
                     const std::vector<int>* second = nullptr) {
  const std::string r = responses;
  ASSERT_EQ(first.size(), r.size());
  for (std::size_t trial = 0; trial < first.size(); ++trial) {
    ASSERT_DOUBLE_EQ(q.next_stimulus()[0], first[trial]) << "trial " << trial;
    if (second != nullptr) {
      ASSERT_DOUBLE_EQ(q.next_stimulus()[1], (*second)[trial]) << "trial " << trial;
    }
    q.add_response(r[trial] == 'C');
  }
}

double mode_of(const QuestPlus& q, const std::string& name) {
  for (const ParameterSummary& s : q.summary())
    if (s.name == name) return s.mode;
  throw std::invalid_argument("no parameter " + name);
}

// Watson 2017 Example 1, "Estimation of contrast threshold {1, 1, 2}" (test_threshold).
const std::vector<int> kExample1Contrasts_dB = {
    -18, -22, -25, -28, -30, -22, -13, -15, -16, -18, -19, -20, -21, -22, -23, -19,
    -20, -20, -18, -18, -19, -17, -17, -18, -18, -18, -19, -19, -19, -19, -19, -19,
};
const char* const kExample1Responses =
    "CCCCIICCCCCCCCICCICCICCCCCCCCCCC";
// Watson 2017 "Implementation": threshold and slope (test_threshold_slope).
const std::vector<int> kThresholdSlopeContrasts_dB = {
    -18, -22, -12, -13, -15, -16, -17, -18, -19, -21, -24, -25, -26, -27, -21, -22,
    -23, -20, -20, -20, -21, -19, -19, -20, -20, -20, -19, -19, -19, -19, -19, -20,
    -20, -20, -20, -20, -21, -21, -20, -20, -20, -19, -18, -18, -19, -19, -19, -18,
    -18, -17, -18, -18, -18, -17, -17, -17, -17, -17, -17, -17, -18, -18, -18, -18,
};
const char* const kThresholdSlopeResponses =
    "CICCCCCCCCCCCICCICCCICCCCICCCCCCCCCCCICCIICCCCICICCCICCCCCCCCCCC";
// Watson 2017 Example 2, "Estimation of contrast threshold, slope, and lapse {1, 3, 2}"
// (test_threshold_slope_lapse).
const std::vector<int> kExample2Contrasts_dB = {
    -18, -22, -25, -28, -30, -21, -12, -14, -15, -16, -18, -19, -20, -22, -23, -18,
    -19, -16, -17, -17, -18, -18, -18, -19, -19, -17, -17, -18, -18, -18, -18, -19,
    -19, -20, -18, -18, -18, -18, -18, -19, -19, -19, -19, -20, -18, -18, -18, -18,
    -18, -18, -18, -18, -18, -19, -19, -19, -20, -18, -18, -18, -18, -19, -19, -19,
    -18, -18, -18, -18, -19, -19, -19, -19, -19, -19, -19, -19, -20, -21, -19, -19,
    -19, -19, -19, -19, -19, -18, -19, -19, -16, -16, -16, -16, -16, -16, 0, 0,
    -19, -19, -19, -19, -19, -19, -19, -19, -19, -19, -19, -19, -19, -19, -21, -21,
    -19, -19, -19, -19, -19, -19, -19, -19, -19, -19, -19, -19, -19, -19, -19, -19,
};
const char* const kExample2Responses =
    "CCCCIICCCCCCCCICICCCCCCCICCCCCCCCICCCCCCCCCICCCICCCCCCCCICCCCCCI"
    "CCCCCCCCCCCCCICICCCCICCICCCCCCCICCCCCCCCCCCCCCCICCCICIICCCCICCCC";
// Watson 2017 Example 3, "Estimation of mean, standard deviation, and lapse {1, 3, 2}"
// (test_mean_sd_lapse).
const std::vector<int> kExample3Orientations_deg = {
    0, -1, 2, -2, 2, 3, 3, -5, 3, 3, 3, 3, -7, -7, -7, -7,
    4, -7, 4, 4, 4, -8, -8, -8, 4, -8, 4, -8, -7, 4, -7, -7,
    4, -7, 4, -7, -6, 3, -4, -5, 3, 3, -7, 2, 2, 1, 0, -7,
    -6, -6, -6, 2, -5, 2, -6, -5, 3, -5, -5, 3, 4, -5, -5, 4,
    -4, -4, -4, -4, 4, 3, 3, 4, 5, 5, -5, 5, -5, -5, 4, 5,
    5, -5, -4, -4, -4, -4, 5, -4, -4, -3, 4, 4, 5, 5, -4, 5,
    -4, -4, 5, 4, 5, 5, -5, 5, -4, -4, -4, -4, 5, -4, 5, 4,
    -4, 4, -4, -4, -4, 4, -4, -4, -4, 4, 4, -4, 4, 4, 4, -4,
};
const char* const kExample3Responses =
    "CIICCCCCCCICIIIICCICCIIICICIICIICICIICICCCICCCIIIIICIIIICIIICIIC"
    "IIICCCIICCICIIICCIIIIICIICCICCICICCICCICIIIICCCCICIIICIIIICCCCCI";
// Watson 2017 Example 4, "Contrast sensitivity function {2, 3, 2}"
// (test_spatial_contrast_sensitivity).
const std::vector<int> kExample4Contrasts_dB = {
    0, -4, 0, 0, -38, 0, -40, 0, -26, -26, 0, -36, -36, 0, -26, -26,
    -2, -26, -6, -26, 0, -26, 0, -26, -32, -32, -34, -34, 0, -26, 0, -26,
};
const std::vector<int> kExample4SpatialFrequencies_cpd = {
    40, 40, 34, 36, 0, 38, 0, 38, 18, 18, 40, 0, 0, 40, 20, 20,
    40, 22, 40, 20, 40, 18, 40, 18, 0, 0, 0, 0, 40, 18, 38, 18,
};
const char* const kExample4Responses =
    "CICCCCICCCCCICCCCCIICCCCCCCIICCC";

// Watson's Weibull in dB: x and threshold in dB, slope 3.5 (Examples 1 and 2) on the contrast
// grid -40..0 dB, guess 0.5, lapse 0.02 unless a grid is given.
QuestPlusSpec weibull_db_spec(std::vector<double> slopes, std::vector<double> lapses) {
  QuestPlusSpec spec;
  spec.shape = PsychometricShape::weibull;
  spec.scale = StimulusScale::db;
  spec.stimulus = {{"intensity", integers(-40, 0)}};
  spec.parameters = {axis("threshold", ParameterRole::threshold, integers(-40, 0)),
                     axis("slope", ParameterRole::slope, std::move(slopes)),
                     axis("lower_asymptote", ParameterRole::guess, {0.5}),
                     axis("lapse_rate", ParameterRole::lapse, std::move(lapses))};
  spec.max_trials = 1000;
  return spec;
}

TEST(QuestPlusWatson2017, Example1ThresholdEveryStimulus) {
  QuestPlus q(weibull_db_spec({3.5}, {0.02}));
  expect_sequence(q, kExample1Contrasts_dB, kExample1Responses);
  EXPECT_EQ(mode_of(q, "threshold"), -20.0);
}

TEST(QuestPlusWatson2017, ThresholdAndSlopeEveryStimulus) {
  QuestPlus q(weibull_db_spec(integers(2, 5), {0.02}));
  expect_sequence(q, kThresholdSlopeContrasts_dB, kThresholdSlopeResponses);
  EXPECT_EQ(mode_of(q, "threshold"), -20.0);
  EXPECT_EQ(mode_of(q, "slope"), 3.0);
}

TEST(QuestPlusWatson2017, Example2ThresholdSlopeLapseEveryStimulus) {
  QuestPlus q(weibull_db_spec(integers(2, 5), numpy_arange(0.0, 0.04 + 0.01, 0.01)));
  expect_sequence(q, kExample2Contrasts_dB, kExample2Responses);
  EXPECT_EQ(mode_of(q, "threshold"), -20.0);
  EXPECT_EQ(mode_of(q, "slope"), 5.0);
  EXPECT_DOUBLE_EQ(mode_of(q, "lapse_rate"), 0.04);
}

TEST(QuestPlusWatson2017, Example3MeanSdLapseEveryStimulus) {
  // questplus's norm_cdf_2: lapse + (1 - 2 lapse) Phi((x - mean) / sd), orientations in degrees.
  QuestPlusSpec spec;
  spec.shape = PsychometricShape::normal;
  spec.guess_equals_lapse = true;
  spec.stimulus = {{"intensity", integers(-10, 10)}};
  spec.parameters = {axis("mean", ParameterRole::threshold, integers(-5, 5)),
                     axis("sd", ParameterRole::sd, integers(1, 10)),
                     axis("lapse_rate", ParameterRole::lapse, numpy_arange(0.0, 0.04 + 0.01, 0.01))};
  spec.max_trials = 1000;
  QuestPlus q(spec);
  expect_sequence(q, kExample3Orientations_deg, kExample3Responses);
  EXPECT_EQ(mode_of(q, "mean"), 0.0);
  EXPECT_EQ(mode_of(q, "sd"), 4.0);
  EXPECT_DOUBLE_EQ(mode_of(q, "lapse_rate"), 0.01);
}

TEST(QuestPlusWatson2017, Example4ContrastSensitivityEveryStimulus) {
  // Two stimulus dimensions that vary (contrast in dB, spatial frequency in cycles/deg) and a
  // third fixed one (temporal frequency 0 Hz); threshold max(min_thresh, c0 + cf f + cw w).
  QuestPlusSpec spec;
  spec.shape = PsychometricShape::weibull;
  spec.scale = StimulusScale::db;
  spec.stimulus = {{"contrast", integers(-50, 0, 2)}, {"spatial_freq", integers(0, 40, 2)}, {"temporal_freq", {0.0}}};
  spec.parameters = {axis("min_thresh", ParameterRole::threshold_floor, integers(-50, -30, 2)),
                     axis("c0", ParameterRole::threshold, integers(-60, -40, 2)),
                     axis("cf", ParameterRole::threshold_coefficient, numpy_arange(0.8, 1.6 + 0.2, 0.2), 1),
                     axis("cw", ParameterRole::threshold_coefficient, {0.0}, 2),
                     axis("slope", ParameterRole::slope, {3.0}),
                     axis("lower_asymptote", ParameterRole::guess, {0.5}),
                     axis("lapse_rate", ParameterRole::lapse, {0.01})};
  spec.max_trials = 1000;
  QuestPlus q(spec);
  expect_sequence(q, kExample4Contrasts_dB, kExample4Responses, &kExample4SpatialFrequencies_cpd);
  EXPECT_EQ(mode_of(q, "min_thresh"), -32.0);
  EXPECT_EQ(mode_of(q, "c0"), -56.0);
  EXPECT_DOUBLE_EQ(mode_of(q, "cf"), 1.4);
}

// ---- Closed forms ----

TEST(QuestPlusClosedForm, PsychometricFunctionsAtThreshold) {
  QuestPlusSpec spec = weibull_db_spec({3.5}, {0.02});
  // Weibull: at x = t, 10^0 = 1, so Q = 1 - lapse - (1 - guess - lapse) e^-1.
  EXPECT_DOUBLE_EQ(quest_plus_probability_correct(spec, {-20.0}, {-20.0, 3.5, 0.5, 0.02}),
                   1.0 - 0.02 - 0.48 * std::exp(-1.0));
  // 20 dB above threshold with slope 1: 10^(1 * 20 / 20) = 10.
  EXPECT_DOUBLE_EQ(quest_plus_probability_correct(spec, {0.0}, {-20.0, 1.0, 0.5, 0.02}),
                   1.0 - 0.02 - 0.48 * std::exp(-10.0));
  spec.scale = StimulusScale::log10;  // one log unit above threshold, slope 1: 10^1
  EXPECT_DOUBLE_EQ(quest_plus_probability_correct(spec, {1.0}, {0.0, 1.0, 0.5, 0.02}),
                   1.0 - 0.02 - 0.48 * std::exp(-10.0));
  spec.scale = StimulusScale::linear;  // (x / t)^beta = 2^2
  EXPECT_DOUBLE_EQ(quest_plus_probability_correct(spec, {4.0}, {2.0, 2.0, 0.5, 0.02}),
                   1.0 - 0.02 - 0.48 * std::exp(-4.0));
  spec.shape = PsychometricShape::logistic;  // halfway between guess and 1 - lapse at x = t
  EXPECT_DOUBLE_EQ(quest_plus_probability_correct(spec, {3.0}, {3.0, 2.0, 0.5, 0.02}), 0.5 + 0.48 / 2.0);
  EXPECT_DOUBLE_EQ(quest_plus_probability_correct(spec, {4.0}, {3.0, 2.0, 0.5, 0.02}),
                   0.5 + 0.48 / (1.0 + std::exp(-2.0)));
  spec.parameters[1] = axis("sd", ParameterRole::sd, {1.0});
  spec.shape = PsychometricShape::normal;  // Phi(0) = 1/2; Phi(1) = (1 + erf(1/sqrt 2)) / 2
  EXPECT_DOUBLE_EQ(quest_plus_probability_correct(spec, {3.0}, {3.0, 2.0, 0.5, 0.02}), 0.5 + 0.48 / 2.0);
  EXPECT_NEAR(quest_plus_probability_correct(spec, {5.0}, {3.0, 2.0, 0.5, 0.02}),
              0.5 + 0.48 * 0.5 * (1.0 + std::erf(1.0 / std::sqrt(2.0))), 1e-15);
}

// One parameter with two grid points and two stimuli, worked by hand: the prior is 1/2 each;
// after a response the posterior is Q_i / (Q_a + Q_b) (or with 1 - Q); E(x) is the expected
// binary entropy.
TEST(QuestPlusClosedForm, OneParameterByHand) {
  QuestPlusSpec spec;
  spec.shape = PsychometricShape::logistic;
  spec.stimulus = {{"intensity", {-1.0, 0.5}}};
  spec.parameters = {axis("threshold", ParameterRole::threshold, {-1.0, 1.0}),
                     axis("slope", ParameterRole::slope, {2.0}),
                     axis("lapse", ParameterRole::lapse, {0.0})};
  spec.fixed_guess = 0.0;
  QuestPlus q(spec);
  auto logistic = [](double x, double t) { return 1.0 / (1.0 + std::exp(-2.0 * (x - t))); };
  auto binary_entropy = [](double p) { return -(p * std::log(p) + (1.0 - p) * std::log(1.0 - p)); };
  auto expected_entropy = [&](double x, double prior_a) {
    const double qa = logistic(x, -1.0), qb = logistic(x, 1.0);
    const double p_correct = prior_a * qa + (1 - prior_a) * qb;
    const double p_incorrect = 1.0 - p_correct;
    return p_correct * binary_entropy(prior_a * qa / p_correct) +
           p_incorrect * binary_entropy(prior_a * (1 - qa) / p_incorrect);
  };
  const std::vector<double> e = q.expected_entropies();
  EXPECT_NEAR(e[0], expected_entropy(-1.0, 0.5), 1e-14);
  EXPECT_NEAR(e[1], expected_entropy(0.5, 0.5), 1e-14);
  EXPECT_EQ(q.next_stimulus_index(), e[0] < e[1] ? 0u : 1u);
  EXPECT_NEAR(q.entropy(), std::log(2.0), 1e-15);

  q.add_response(1, true);  // correct at x = 0.5
  const double qa = logistic(0.5, -1.0), qb = logistic(0.5, 1.0);
  EXPECT_NEAR(q.posterior()[0], qa / (qa + qb), 1e-15);
  EXPECT_NEAR(q.posterior()[1], qb / (qa + qb), 1e-15);
  const double pa = qa / (qa + qb);
  const std::vector<double> e1 = q.expected_entropies();
  EXPECT_NEAR(e1[0], expected_entropy(-1.0, pa), 1e-14);
  EXPECT_NEAR(e1[1], expected_entropy(0.5, pa), 1e-14);
  const std::vector<ParameterSummary> s = q.summary();
  EXPECT_EQ(s[0].mode, -1.0);  // the larger posterior
  EXPECT_NEAR(s[0].mean, -pa + (1 - pa), 1e-15);
  EXPECT_NEAR(s[0].sd, std::sqrt(1.0 - (1 - 2 * pa) * (1 - 2 * pa)), 1e-14);  // values +-1
  EXPECT_EQ(s[1].sd, 0.0);  // a fixed parameter
}

TEST(QuestPlusClosedForm, PosteriorStaysNormalisedAndPriorIsTheProductOfWeights) {
  QuestPlusSpec spec = weibull_db_spec(integers(2, 5), numpy_arange(0.0, 0.05, 0.01));
  spec.parameters[0].prior.assign(41, 1.0);
  spec.parameters[0].prior[20] = 3.0;  // threshold -20 dB three times as likely a priori
  spec.parameters[1].prior = {1.0, 2.0, 3.0, 4.0};
  QuestPlus q(spec);
  // P0(t, slope) = w_t w_slope / (sum w_t)(sum w_slope), lapse uniform over 5.
  const std::vector<double> marginal_slope = q.marginal(1);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(marginal_slope[i], (i + 1) / 10.0, 1e-15);
  EXPECT_NEAR(q.marginal(0)[20], 3.0 / 43.0, 1e-15);
  EXPECT_NEAR(q.marginal(3)[2], 0.2, 1e-15);
  for (int trial = 0; trial < 20; ++trial) {
    q.add_response(trial % 3 != 0);
    double total = 0.0;
    for (double p : q.posterior()) total += p;
    EXPECT_NEAR(total, 1.0, 1e-12);
  }
}

TEST(QuestPlus, TiesGoToTheFirstGridPoint) {
  QuestPlusSpec spec = weibull_db_spec({3.5}, {0.02});
  // The same intensity three times: equal expected entropies, the first is chosen.
  spec.stimulus = {{"intensity", {-20.0, -20.0, -20.0}}};
  QuestPlus q(spec);
  EXPECT_EQ(q.next_stimulus_index(), 0u);
  // Two dimensions: a second dimension with no effect ties all its values; the first wins.
  spec.stimulus = {{"intensity", integers(-40, 0)}, {"unused", {7.0, 8.0}}};
  QuestPlus q2(spec);
  EXPECT_EQ(q2.next_stimulus_index() % 2, 0u);
  EXPECT_EQ(q2.next_stimulus()[0], -18.0);  // Example 1's first stimulus
}

TEST(QuestPlus, StopsAtTrialCountOrPosteriorSd) {
  QuestPlusSpec spec = weibull_db_spec({3.5}, {0.02});
  spec.max_trials = 5;
  QuestPlus q(spec);
  for (int i = 0; i < 5; ++i) {
    EXPECT_FALSE(q.finished());
    q.add_response(true);
  }
  EXPECT_TRUE(q.finished());

  spec.max_trials = 1000;
  spec.stop_sd = 3.0;  // dB
  spec.min_trials = 4;
  QuestPlus by_sd(spec);
  const std::string r = kExample1Responses;
  int trials = 0;
  while (!by_sd.finished()) by_sd.add_response(r[static_cast<std::size_t>(trials++)] == 'C');
  EXPECT_GE(trials, 4);
  EXPECT_LE(by_sd.summary()[0].sd, 3.0);
  // One trial earlier the SD was still above the limit (or the minimum count was not reached).
  QuestPlus replay(spec);
  for (int i = 0; i + 1 < trials; ++i) replay.add_response(r[static_cast<std::size_t>(i)] == 'C');
  EXPECT_TRUE(trials - 1 < 4 || replay.summary()[0].sd > 3.0);
}

TEST(QuestPlus, PsiDefaults) {
  const std::vector<double> slopes = psi_default_slopes();
  ASSERT_EQ(slopes.size(), 41u);
  EXPECT_NEAR(slopes.front(), 0.1, 1e-15);
  EXPECT_DOUBLE_EQ(slopes[20], 1.0);
  EXPECT_NEAR(slopes.back(), 10.0, 1e-14);
  const QuestPlusSpec spec = make_psi_spec(integers(-2, 2), integers(-2, 2), 0.5);
  EXPECT_EQ(spec.scale, StimulusScale::log10);
  QuestPlus q(spec);
  EXPECT_EQ(q.parameter_count(), 5u * 41u);
}

TEST(QuestPlus, RefusesSpecsItCannotRun) {
  auto refuses = [](QuestPlusSpec spec, const std::string& part) {
    try {
      QuestPlus q(std::move(spec));
      ADD_FAILURE() << "accepted; expected an error naming " << part;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  QuestPlusSpec base = weibull_db_spec({3.5}, {0.02});
  QuestPlusSpec s = base;
  s.stimulus.clear();
  refuses(s, "stimulus dimension");
  s = base;
  s.parameters.erase(s.parameters.begin());
  refuses(s, "threshold");
  s = base;
  s.parameters[0].prior = {1.0, 2.0};
  refuses(s, "2 weights for 41");
  s = base;
  s.parameters[3].values = {0.6};
  refuses(s, "guess + lapse");
  s = base;
  s.shape = PsychometricShape::normal;
  refuses(s, "sd");
  s = base;
  s.stop_sd = 1.0;
  s.stop_sd_parameter = "thresh";
  refuses(s, "stop_sd names no parameter 'thresh'");
  s = base;
  s.parameters.push_back(axis("c", ParameterRole::threshold_coefficient, {1.0}, 1));
  refuses(s, "stimulus dimension after the first");
  s = base;
  s.stimulus[0].values.push_back(std::nan(""));
  refuses(s, "not finite");
}

}  // namespace
}  // namespace glarelab

// Forced choice with a graded variable (analysis/graded_choice_analysis.h) on the design of
// examples/glare_brightness.toml: the example's own trial plans (build_forced_choice_trials, the
// scenes' peaks read from their files) answered by the simulated observer of the same file
// (protocols/simulated_observer.cpp) with 40 seeds, straight into the analysis, without rendering
// a session (a full session renders 144 trials x 30 frames with glare; the responses would be the
// same, since the observer answers from the trial plan alone).
//
// The observer: a side in glare mode m looks (1 + b_m) times its luminance (b_static = 0.10,
// b_dynamic = 0.25, b_control = 0), and the side with the larger perceived log10 luminance after
// N(0, 0.10^2) noise on the difference is named. The reference (scene_a) carries the glare, the
// comparison (scene_b) none, so P(scene_b named) = Phi((log10 ratio - log10(1 + b_m)) / 0.10) and
// the PSE of glare mode m is exactly log10(1 + b_m) on the analysis' log10-ratio axis.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "analysis/graded_choice_analysis.h"
#include "analysis/loaded_database.h"
#include "cli_process.h"
#include "protocols/experiment.h"
#include "protocols/forced_choice.h"
#include "protocols/observer.h"
#include "scipy_support.h"
#include "scratch_dir.h"
#include "stimuli/scene_library.h"

namespace glarelab::analysis {
namespace {

const std::string kExample = std::string(GLARELAB_SOURCE_DIR) + "/examples/glare_brightness.toml";

struct Design {
  Experiment experiment;
  std::vector<TrialPlan> plans;
};

Design load_design(const std::string& path) {
  Design d;
  d.experiment = load_experiment(path);
  const SceneLibrary scenes(d.experiment.scenes, d.experiment.display);
  d.plans = build_forced_choice_trials(d.experiment, scenes.peak_luminances_cd_m2());
  return d;
}

const Design& example_design() {
  static const Design design = load_design(kExample);
  return design;
}

LoadedData simulate(const Design& design, std::uint64_t seed) {
  const auto observer = make_simulated_observer(design.experiment.simulated_observer, seed);
  LoadedSession session;
  session.label = "simulated " + std::to_string(seed);
  for (const TrialPlan& plan : design.plans) {
    LoadedTrial trial;
    trial.record.trial_index = plan.trial_index;
    trial.record.procedure = plan.procedure;
    trial.record.condition = plan.condition_json;
    trial.record.response = observer->respond(plan).value;
    trial.condition = parse_condition_json(plan.condition_json);
    session.trials.push_back(std::move(trial));
  }
  LoadedData data;
  data.sessions.push_back(std::move(session));
  return data;
}

// log10(1 + b) of a glare mode's brightening b (0 for a mode without one).
double brightening_log10(const Experiment& experiment, const std::string& mode) {
  const auto& brightening = experiment.simulated_observer.glare_mode_brightening;
  const auto found = brightening.find(mode);
  return std::log10(1.0 + (found == brightening.end() ? 0.0 : found->second));
}

// The glare every trial of the design shows on one side: the comparison's (control in the example,
// static in the demo).
std::string comparison_glare(const Design& design) {
  std::set<std::string> common(design.plans.front().position_glare.begin(), design.plans.front().position_glare.end());
  for (const TrialPlan& plan : design.plans) {
    std::set<std::string> kept;
    for (const std::string& mode : plan.position_glare)
      if (common.contains(mode)) kept.insert(mode);
    common = kept;
  }
  return common.size() == 1 ? *common.begin() : "control";
}

// The observer matches the two sides' perceived log luminances: the comparison with its own glare
// matches the reference with `mode` at log10 ratio log10(1 + b_mode) - log10(1 + b_comparison).
double true_pse_log10(const Design& design, const std::string& mode) {
  return brightening_log10(design.experiment, mode) - brightening_log10(design.experiment, comparison_glare(design));
}

const GradedChoiceGroup* group_named(const GradedChoiceAnalysis& analysis, const std::string& name) {
  for (const GradedChoiceGroup& group : analysis.groups)
    if (group.name == name) return &group;
  return nullptr;
}

TEST(PseGradedChoice, ExampleObserverHasTheStatedBrightening) {
  const Experiment& e = example_design().experiment;
  EXPECT_DOUBLE_EQ(e.simulated_observer.glare_mode_brightening.at("static"), 0.10);
  EXPECT_DOUBLE_EQ(e.simulated_observer.glare_mode_brightening.at("dynamic"), 0.25);
  EXPECT_DOUBLE_EQ(e.simulated_observer.appearance_sd_log10, 0.10);
  // 17 rows (6 ratios x 3 modes, less control at ratio 1) x 4 repetitions x 2 sides.
  EXPECT_EQ(example_design().plans.size(), 136u);
}

// The stored configuration keeps the brightening (a resumed session answers alike); a mode that
// is not a glare mode is refused at its key.
TEST(PseGradedChoice, GlareModeBrighteningIsStoredAndChecked) {
  const Experiment& e = example_design().experiment;
  const Experiment reread = parse_experiment_text(resolved_config_toml(e), "<stored config>", "/");
  EXPECT_EQ(reread.simulated_observer.glare_mode_brightening, e.simulated_observer.glare_mode_brightening);
  std::string text = test::read_bytes(kExample);
  const std::string base = std::string(GLARELAB_SOURCE_DIR) + "/examples";
  text.replace(text.find("dynamic = 0.25"), 14, "dynamc = 0.25");
  try {
    parse_experiment_text(text, "bad.toml", base);
    ADD_FAILURE() << "a misspelt glare mode was accepted";
  } catch (const ConfigError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("observer.simulated.glare_mode_brightening.dynamc"), std::string::npos) << message;
    EXPECT_NE(message.find("bad.toml:"), std::string::npos) << message;
  }
}

// The observer's choice probability against the closed form Phi((d - log10(1 + b)) / sd): 20,000
// trials at one ratio, the count within 4 binomial standard errors.
TEST(PseGradedChoice, ObserverFollowsTheCumulativeNormalOfPerceivedLuminance) {
  SimulatedObserverSpec spec;
  spec.appearance_sd_log10 = 0.08;
  spec.glare_mode_brightening = {{"dynamic", 0.25}};
  const auto observer = make_simulated_observer(spec, 11);
  TrialPlan plan;
  plan.procedure = "forced_choice";
  plan.allowed_responses = {"left", "right"};
  plan.source_luminance_cd_m2 = {130.0, 160.0};  // reference left with dynamic glare, comparison right
  plan.position_glare = {"dynamic", "control"};
  plan.correct_response = "right";
  const int n = 20000;
  int comparison = 0;
  for (int i = 0; i < n; ++i) {
    plan.trial_index = i;
    comparison += observer->respond(plan).value == "right" ? 1 : 0;
  }
  const double d = std::log10(160.0 / 130.0) - std::log10(1.25);
  const double p = 0.5 * std::erfc(-d / 0.08 / std::sqrt(2.0));
  EXPECT_NEAR(static_cast<double>(comparison) / n, p, 4.0 * std::sqrt(p * (1 - p) / n)) << "expected " << p;
}

// The known PSE of every glare mode inside its 95 % interval in at least 36 of 40 seeded runs; so
// is the known shift of static and dynamic from control. For this example and for the demo
// (examples/demo.toml), which asks the same question with one answer per side, ratio and mode.
class KnownPse : public ::testing::TestWithParam<const char*> {};

TEST_P(KnownPse, PerGlareModeIsRecoveredInAtLeast36Of40Runs) {
  const Design design = load_design(std::string(GLARELAB_SOURCE_DIR) + "/examples/" + GetParam());
  GradedChoiceOptions options;
  // The intervals checked are the posterior's (the PSE's and the shift's); the maximum-likelihood
  // fit's parametric bootstrap (200 refits per group by default) feeds neither.
  options.bootstrap_samples = 0;
  options.threads = 2;
  std::map<std::string, int> pse_inside, shift_inside, fitted, estimated;
  std::map<std::string, double> pse_sum, pse_sum2;
  const std::vector<std::string> modes = {"control", "static", "dynamic"};
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    options.seed = seed;
    const GradedChoiceAnalysis analysis = analyse_graded_choice(simulate(design, seed), options);
    ASSERT_EQ(analysis.variable, "luminance_ratio");
    ASSERT_TRUE(analysis.log10_axis);
    ASSERT_EQ(analysis.baseline, "control");
    ASSERT_EQ(analysis.groups.size(), 3u);
    for (const std::string& mode : modes) {
      const GradedChoiceGroup* group = group_named(analysis, mode);
      ASSERT_NE(group, nullptr) << mode;
      if (group->fit.ok()) ++fitted[mode];
      if (!group->posterior) continue;
      const double truth = true_pse_log10(design, mode);
      ++estimated[mode];
      pse_sum[mode] += *group->pse();
      pse_sum2[mode] += *group->pse() * *group->pse();
      const Interval& pse = group->posterior->credible;
      pse_inside[mode] += pse.low <= truth && truth <= pse.high ? 1 : 0;
      if (mode == "control" || !group->shift_interval) continue;
      const double shift = truth - true_pse_log10(design, "control");
      const Interval& interval = *group->shift_interval;
      shift_inside[mode] += interval.low <= shift && shift <= interval.high ? 1 : 0;
    }
  }
  for (const std::string& mode : modes) {
    std::printf("%s: PSE inside its interval in %d of 40 runs (%d with an ML fit), mean PSE %.4f, true %.4f", mode.c_str(),
                pse_inside[mode], fitted[mode], pse_sum[mode] / std::max(estimated[mode], 1),
                true_pse_log10(design, mode));
    if (mode != "control") std::printf("; shift inside in %d", shift_inside[mode]);
    std::printf("\n");
    EXPECT_GE(pse_inside[mode], 36) << mode;
    EXPECT_EQ(estimated[mode], 40) << mode << ": every run has a posterior";
    // The estimator is unbiased: the mean of the runs' PSEs lies within three standard errors of
    // the truth (one run's spread is about 0.015 log10 units in the example, 0.03 in the demo).
    const double count = std::max(estimated[mode], 2);
    const double mean = pse_sum[mode] / count;
    const double standard_error = std::sqrt((pse_sum2[mode] / count - mean * mean) * count / (count - 1.0) / count);
    std::printf("  mean PSE %.4f, standard error of the mean %.4f\n", mean, standard_error);
    EXPECT_NEAR(mean, true_pse_log10(design, mode), std::max(3.0 * standard_error, 0.002)) << mode;
    if (mode != "control") {
      EXPECT_GE(shift_inside[mode], 36) << mode;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Examples, KnownPse, ::testing::Values("glare_brightness.toml", "demo.toml"),
                         [](const ::testing::TestParamInfo<const char*>& example) {
                           return std::string(example.param).substr(0, std::string(example.param).find('.'));
                         });

// The likelihood-ratio test of one shared PSE against the same maximisation by SciPy
// (scipy.optimize.minimize, Nelder-Mead from several starts) on one simulated run.
TEST(PseGradedChoice, SharedPseLikelihoodRatioAgreesWithSciPy) {
  std::string why;
  if (!test::scipy_available(why)) GTEST_SKIP() << why;
  GradedChoiceOptions options;
  options.bootstrap_samples = 0;
  const GradedChoiceAnalysis analysis = analyse_graded_choice(simulate(example_design(), 3), options);
  ASSERT_TRUE(analysis.shared_pse.ok()) << analysis.shared_pse.unavailable;
  const test::ScratchDir scratch;
  const std::string csv = (scratch.path() / "levels.csv").string();
  {
    std::ofstream out(csv);
    for (std::size_t g = 0; g < analysis.groups.size(); ++g)
      for (const StimulusLevel& level : analysis.groups[g].levels)
        out << g << "," << level.intensity << "," << level.trials << "," << level.correct << "\n";
  }
  const std::string script = (scratch.path() / "lr.py").string();
  std::ofstream(script) << R"(import sys
import numpy as np
from scipy.optimize import minimize
from scipy.special import log_ndtr
rows = np.loadtxt(sys.argv[1], delimiter=",")
groups = sorted(set(rows[:, 0].astype(int)))
def nll(rows, mu, beta):
    z = beta * (rows[:, 1] - mu)
    return -np.sum(rows[:, 3] * log_ndtr(z) + (rows[:, 2] - rows[:, 3]) * log_ndtr(-z))
def best(f, starts):
    results = [minimize(f, s, method="Nelder-Mead", options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 40000, "maxfev": 40000}) for s in starts]
    return min(results, key=lambda r: r.fun)
separate = 0.0
for g in groups:
    r = rows[rows[:, 0] == g]
    separate += best(lambda p: nll(r, p[0], np.exp(p[1])), [[m, b] for m in (-0.05, 0.0, 0.05, 0.1) for b in (1.0, 2.5, 4.0)]).fun
k = len(groups)
shared = best(lambda p: sum(nll(rows[rows[:, 0] == g], p[0], np.exp(p[1 + i])) for i, g in enumerate(groups)),
              [[m] + [b] * k for m in (0.0, 0.05) for b in (2.0, 3.0)])
print("G %.10f mu %.10f" % (2.0 * (shared.fun - separate), shared.x[0]))
)";
  const std::string output = test::run_python(script, csv);
  double statistic = 0.0, mu = 0.0;
  ASSERT_EQ(std::sscanf(output.c_str(), "G %lf mu %lf", &statistic, &mu), 2) << output;
  EXPECT_NEAR(analysis.shared_pse.statistic, statistic, 1e-5 * std::max(1.0, statistic)) << output;
  EXPECT_NEAR(analysis.shared_pse.shared_pse, mu, 1e-4) << output;
  EXPECT_EQ(analysis.shared_pse.df, 2);
  std::printf("G = %.6f (SciPy %.6f), p = %.3g, shared PSE %.5f (SciPy %.5f)\n", analysis.shared_pse.statistic, statistic,
              analysis.shared_pse.p_value, analysis.shared_pse.shared_pse, mu);
}

// The PSE posterior (analysis/pse_posterior.h) of each glare mode and the shift from control, on
// one simulated run of the demo, against SciPy on a grid four times finer in each direction
// (1601 x 801), the priors written again from the header's words, the marginal's quantiles by
// interpolating its trapezoid cumulative and the shift's by convolving the two marginals: the
// credible intervals and medians agree within 2e-3 log10 units (1/150 of the tested range), the
// discretisation of the product's 401 x 201 grid.
TEST(PseGradedChoice, PosteriorIntervalsAgreeWithAFinerGridInSciPy) {
  std::string why;
  if (!test::scipy_available(why)) GTEST_SKIP() << why;
  GradedChoiceOptions options;
  options.bootstrap_samples = 0;
  const Design design = load_design(std::string(GLARELAB_SOURCE_DIR) + "/examples/demo.toml");
  const GradedChoiceAnalysis analysis = analyse_graded_choice(simulate(design, 3), options);
  ASSERT_EQ(analysis.groups.size(), 3u);
  const test::ScratchDir scratch;
  const std::string csv = (scratch.path() / "levels.csv").string();
  {
    std::ofstream out(csv);
    out.precision(17);
    for (std::size_t g = 0; g < analysis.groups.size(); ++g) {
      ASSERT_TRUE(analysis.groups[g].posterior) << analysis.groups[g].name;
      for (const StimulusLevel& level : analysis.groups[g].levels)
        out << g << "," << level.intensity << "," << level.trials << "," << level.correct << "\n";
    }
  }
  const std::string script = (scratch.path() / "posterior.py").string();
  std::ofstream(script) << R"(import sys
import numpy as np
from scipy.special import log_ndtr, ndtri
rows = np.loadtxt(sys.argv[1], delimiter=",")
def ramp(v, zero, one):
    t = np.clip((v - zero) / (one - zero), 0.0, 1.0)
    return 0.5 - 0.5 * np.cos(np.pi * t)
def marginal(r):
    x = np.unique(r[:, 1]); lo, hi = x.min(), x.max(); rng = hi - lo; step = np.diff(x).min()
    mu = np.linspace(lo - 0.5 * rng, hi + 0.5 * rng, 1601)
    logw = np.linspace(np.log(step), np.log(6 * rng), 801); w = np.exp(logw)
    pm = np.where(mu < lo, ramp(mu, lo - 0.5 * rng, lo), np.where(mu > hi, ramp(mu, hi + 0.5 * rng, hi), 1.0))
    pw = np.where(w < 2 * step, ramp(w, step, 2 * step), np.where(w > 3 * rng, ramp(w, 6 * rng, 3 * rng), 1.0))
    M, W = np.meshgrid(mu, w, indexing="ij")
    z = (M * 0.0)
    ll = np.zeros_like(M)
    for xi, n, k in r[:, 1:]:
        z = (xi - M) * 2.0 * ndtri(0.95) / W
        ll += k * log_ndtr(z) + (n - k) * log_ndtr(-z)
    with np.errstate(divide="ignore"):
        lp = ll + np.log(pm)[:, None] + np.log(pw)[None, :]
    post = np.exp(lp - lp.max())
    m = np.trapz(post, logw, axis=1)
    return mu, m / np.trapz(m, mu)
def quantile(x, density, q):
    c = np.concatenate([[0.0], np.cumsum(0.5 * (density[1:] + density[:-1]) * np.diff(x))])
    return np.interp(q * c[-1], c, x)
marg = {g: marginal(rows[rows[:, 0] == g]) for g in (0, 1, 2)}
for g in (0, 1, 2):
    mu, m = marg[g]
    print("pse %d %.8f %.8f %.8f" % (g, quantile(mu, m, 0.025), quantile(mu, m, 0.975), quantile(mu, m, 0.5)))
grid = np.linspace(-1.0, 1.0, 8001); h = grid[1] - grid[0]
def on_grid(g):
    mu, m = marg[g]
    return np.interp(grid, mu, m, left=0.0, right=0.0)
a = on_grid(0)
for g in (1, 2):
    d = np.convolve(on_grid(g), a[::-1]) * h
    dx = (np.arange(d.size) - (grid.size - 1)) * h
    print("shift %d %.8f %.8f 0" % (g, quantile(dx, d, 0.025), quantile(dx, d, 0.975)))
)";
  const std::string output = test::run_python(script, csv);
  std::istringstream lines(output);
  std::string line;
  int checked = 0;
  while (std::getline(lines, line)) {
    char kind[8];
    int g = 0;
    double low = 0.0, high = 0.0, median = 0.0;
    if (std::sscanf(line.c_str(), "%7s %d %lf %lf %lf", kind, &g, &low, &high, &median) != 5) continue;
    const GradedChoiceGroup& group = analysis.groups.at(static_cast<std::size_t>(g));
    Interval mine;
    if (std::string(kind) == "pse") {
      mine = group.posterior->credible;
      EXPECT_NEAR(group.posterior->median, median, 2e-3) << group.name;
    } else {
      ASSERT_TRUE(group.shift_interval) << line;
      mine = *group.shift_interval;
    }
    EXPECT_NEAR(mine.low, low, 2e-3) << kind << " " << group.name;
    EXPECT_NEAR(mine.high, high, 2e-3) << kind << " " << group.name;
    std::printf("%s %s: [%.5f, %.5f], SciPy's finer grid [%.5f, %.5f]\n", kind, group.name.c_str(), mine.low, mine.high,
                low, high);
    ++checked;
  }
  EXPECT_EQ(checked, 5) << output;
}

// Identical groups: the shared model fits as well as the separate one, G = 0 and p = 1; groups
// whose answers separate perfectly have no test.
TEST(PseGradedChoice, SharedPseTestOnIdenticalAndSeparatedGroups) {
  const std::vector<StimulusLevel> levels = {{-0.1, 10, 2}, {0.0, 10, 5}, {0.1, 10, 8}};
  const SharedPseTest same = shared_pse_test({levels, levels});
  ASSERT_TRUE(same.ok()) << same.unavailable;
  EXPECT_NEAR(same.statistic, 0.0, 1e-9);
  EXPECT_NEAR(same.p_value, 1.0, 1e-6);
  EXPECT_NEAR(same.shared_pse, 0.0, 1e-6);  // the data are symmetric about 0
  const SharedPseTest separated = shared_pse_test({levels, {{-0.1, 10, 0}, {0.0, 10, 0}, {0.1, 10, 10}}});
  EXPECT_FALSE(separated.ok());
}

// Graded trials are the graded analysis' and leave the pair-preference table.
TEST(PseGradedChoice, GradedTrialsAreRecognisedByTheirNumericColumn) {
  const LoadedData data = simulate(example_design(), 1);
  GradedChoiceOptions options;
  options.bootstrap_samples = 0;
  const GradedChoiceAnalysis analysis = analyse_graded_choice(data, options);
  long graded = 0;
  for (const LoadedTrial& trial : data.sessions[0].trials) graded += is_graded_trial(trial, analysis) ? 1 : 0;
  EXPECT_EQ(graded, 136);
  EXPECT_EQ(analysis.trials, 136);
  long answers = 0;
  for (const GradedChoiceGroup& group : analysis.groups)
    for (const StimulusLevel& level : group.levels) answers += level.trials;
  EXPECT_EQ(answers, 136);
  EXPECT_TRUE(analysis.notes.empty());
}

// The example through the real runner and `glarelab analyze`, made small (2 frames per trial at
// 512 x 256, one repetition: 34 trials with static and dynamic glare rendered): the stored trials
// carry what the graded analysis reads (the numeric column, the sides' scenes and glare), every
// answer lands in its glare group, and the report has the section and its figure.
TEST(PseGradedChoice, ExampleRunsOffscreenAndTheReportFitsEachGlareMode) {
  const test::ScratchDir scratch;
  const std::filesystem::path examples = std::filesystem::path(GLARELAB_SOURCE_DIR) / "examples";
  std::istringstream in(test::read_bytes(kExample));
  std::string text, line;
  while (std::getline(in, line)) {
    if (line.rfind("stimulus_frames", 0) == 0) line = "stimulus_frames = 2";
    if (line.rfind("repetitions", 0) == 0) line = "repetitions = 1";
    if (line.rfind("width_px", 0) == 0) line = "width_px = 512";
    if (line.rfind("height_px", 0) == 0) line = "height_px = 256";
    if (const auto at = line.find("\"scenes/"); at != std::string::npos) line.replace(at, 1, "\"" + examples.string() + "/");
    if (line.rfind("file = \"glare_brightness_conditions.csv\"", 0) == 0)
      line = "file = \"" + (examples / "glare_brightness_conditions.csv").string() + "\"";
    text += line + "\n";
  }
  const auto experiment = scratch.path() / "glare_brightness.toml";
  std::ofstream(experiment) << text;
  const auto db = scratch.path() / "run.db";
  const auto run = test::run_glarelab(
      {"run", experiment.string(), "--display", "offscreen", "--observer", "simulated", "--db", db.string()}, scratch.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("34 trials"), std::string::npos) << run.output;

  const LoadedData data = load_databases({db.string()});
  GradedChoiceOptions options;
  options.bootstrap_samples = 0;
  const GradedChoiceAnalysis analysis = analyse_graded_choice(data, options);
  EXPECT_EQ(analysis.variable, "luminance_ratio");
  EXPECT_EQ(analysis.trials, 34);
  EXPECT_TRUE(analysis.notes.empty());
  std::map<std::string, long> answers;
  for (const GradedChoiceGroup& group : analysis.groups)
    for (const StimulusLevel& level : group.levels) answers[group.name] += level.trials;
  EXPECT_EQ(answers["control"], 10);  // 5 ratios x 2 sides
  EXPECT_EQ(answers["static"], 12);
  EXPECT_EQ(answers["dynamic"], 12);

  const auto out = scratch.path() / "analysis";
  const auto analyzed = test::run_glarelab({"analyze", db.string(), "--out", out.string(), "--bootstrap", "20"}, scratch.path());
  ASSERT_EQ(analyzed.exit_code, 0) << analyzed.output;
  EXPECT_NE(analyzed.output.find("graded choice control (log10 luminance_ratio)"), std::string::npos) << analyzed.output;
  const std::string html = test::read_bytes((out / "report.html").string());
  EXPECT_NE(html.find("Forced choice with a graded variable"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(out / "figures" / "graded_choice.svg"));
}

}  // namespace
}  // namespace glarelab::analysis

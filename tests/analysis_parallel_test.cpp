// The analysis at scale: psychometric fits on worker threads give the same numbers for any thread
// count (each fit is seeded by its staircase), and the loader's parse-once cache of condition
// texts gives every trial the fields of its own text.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <stdexcept>

#include "analysis/analysis_report.h"
#include "core/parallel_for.h"
#include "tests/analysis_synthetic.h"
#include "tests/scratch_dir.h"

namespace glarelab::analysis {
namespace {

using test::TrialSpec;

TEST(AnalysisParallel, EveryJobRunsExactlyOnceForAnyThreadCount) {
  for (const std::size_t count : {std::size_t{0}, std::size_t{1}, std::size_t{7}, std::size_t{100}}) {
    for (const unsigned threads : {1u, 2u, 3u, 8u}) {
      std::vector<std::atomic<int>> runs(count);
      parallel_for(count, threads, [&](std::size_t i) { ++runs[i]; });
      for (std::size_t i = 0; i < count; ++i) EXPECT_EQ(runs[i].load(), 1) << count << " jobs, " << threads << " threads";
    }
  }
}

TEST(AnalysisParallel, AJobsExceptionReachesTheCaller) {
  EXPECT_THROW(parallel_for(50, 3,
                                 [](std::size_t i) {
                                   if (i == 17) throw std::runtime_error("job 17");
                                 }),
               std::runtime_error);
}

// Four participants, two interleaved 2AFC staircases each, answers from a seeded logistic observer.
std::string staircase_database(const test::ScratchDir& dir) {
  const std::string path = dir.file("staircases.db");
  ResultStore store(path);
  const CounterRandom random(11, RandomStream::observer);
  for (int p = 0; p < 4; ++p) {
    const auto id = store.begin_session(test::synthetic_session("P" + std::to_string(p)));
    std::vector<TrialSpec> specs;
    for (int t = 0; t < 48; ++t) {
      TrialSpec spec;
      spec.procedure = "staircase";
      spec.staircase = t % 2 == 0 ? "contrast" : "size";
      spec.condition = "{\"name\":\"" + spec.staircase + "\"}";
      spec.intensity = 0.1 + 0.1 * ((t / 2) % 8);
      const double psi = 0.5 + 0.48 / (1.0 + std::exp(-12.0 * (*spec.intensity - 0.45)));
      spec.correct = random.uniform(static_cast<std::uint64_t>(p * 100 + t)) < psi ? 1 : 0;
      spec.response = *spec.correct ? "left" : "right";
      spec.reversal = t % 5 == 0 ? 1 : 0;
      specs.push_back(spec);
    }
    test::commit_trials(store, id, specs);
    store.finish_session(id, "completed");
  }
  return path;
}

void expect_same_fit(const PsychometricFit& a, const PsychometricFit& b) {
  EXPECT_EQ(a.unavailable, b.unavailable);
  EXPECT_EQ(a.threshold, b.threshold);  // bit for bit
  EXPECT_EQ(a.slope, b.slope);
  EXPECT_EQ(a.lapse, b.lapse);
  EXPECT_EQ(a.deviance, b.deviance);
  ASSERT_EQ(a.threshold_ci.has_value(), b.threshold_ci.has_value());
  if (a.threshold_ci) {
    EXPECT_EQ(a.threshold_ci->low, b.threshold_ci->low);
    EXPECT_EQ(a.threshold_ci->high, b.threshold_ci->high);
    EXPECT_EQ(a.slope_ci->low, b.slope_ci->low);
    EXPECT_EQ(a.slope_ci->high, b.slope_ci->high);
  }
  EXPECT_EQ(a.bootstrap_failures, b.bootstrap_failures);
}

TEST(AnalysisParallel, FitsAreIdenticalForOneOrManyThreadsAndMatchSerialFits) {
  const test::ScratchDir dir;
  const LoadedData data = load_databases({staircase_database(dir)});
  StaircaseOptions options;
  options.bootstrap_samples = 40;
  options.seed = 5;
  options.threads = 1;
  const auto serial = analyse_staircases(data, options);
  options.threads = 3;
  const auto threaded = analyse_staircases(data, options);
  ASSERT_EQ(serial.size(), 8u);
  ASSERT_EQ(threaded.size(), serial.size());
  int with_interval = 0;
  for (std::size_t i = 0; i < serial.size(); ++i) {
    ASSERT_EQ(serial[i].fits.size(), 3u);
    ASSERT_EQ(threaded[i].fits.size(), 3u);
    // Independent reference: the fit of the staircase's own trials, called directly, seeded by
    // its position among all staircases.
    std::vector<std::pair<double, bool>> trials;
    for (const StaircasePoint& point : serial[i].track) trials.emplace_back(point.intensity, point.correct);
    const PsychometricShape shapes[] = {PsychometricShape::logistic, PsychometricShape::cumulative_normal,
                                        PsychometricShape::weibull};
    for (std::size_t s = 0; s < 3; ++s) {
      PsychometricFitOptions fit_options;
      fit_options.shape = shapes[s];
      fit_options.guess_rate = serial[i].guess_rate;
      fit_options.bootstrap_samples = 40;
      fit_options.seed = 5 + i;
      const PsychometricFit reference = fit_psychometric(levels_from_trials(trials), fit_options);
      expect_same_fit(serial[i].fits[s], reference);
      expect_same_fit(threaded[i].fits[s], reference);
      with_interval += reference.threshold_ci ? 1 : 0;
    }
  }
  EXPECT_GT(with_interval, 12);  // the comparison covers the bootstrap, not only failed fits
}

TEST(AnalysisParallel, RepeatedConditionTextsParseToTheirOwnFields) {
  const test::ScratchDir dir;
  const std::string path = dir.file("conditions.db");
  const std::vector<std::string> texts = {"{\"scene\":\"Gem\",\"level\":2}", "{\"scene\":\"Park\"}", "not json",
                                          "{\"scene\":\"Gem\",\"level\":2}", "not json", "{\"scene\":\"Park\"}",
                                          "not json"};
  {
    ResultStore store(path);
    const auto id = store.begin_session(test::synthetic_session("A"));
    std::vector<TrialSpec> specs;
    for (const std::string& text : texts) {
      TrialSpec spec;
      spec.procedure = "rating";
      spec.condition = text;
      spec.response = "3";
      specs.push_back(spec);
    }
    test::commit_trials(store, id, specs);
    store.finish_session(id, "completed");
  }
  const LoadedData data = load_databases({path});
  ASSERT_EQ(data.sessions.size(), 1u);
  ASSERT_EQ(data.sessions[0].trials.size(), texts.size());
  for (std::size_t i = 0; i < texts.size(); ++i) {
    const ConditionFields expected =
        texts[i] == "not json" ? ConditionFields{{"name", "not json"}} : parse_condition_json(texts[i]);
    EXPECT_EQ(data.sessions[0].trials[i].condition, expected) << texts[i];
  }
  bool counted = false;
  for (const std::string& note : data.notes) counted = counted || note.find(": 3 trial(s) with a condition") != std::string::npos;
  EXPECT_TRUE(counted) << "every unreadable trial is counted, not only the first of a text";
}

}  // namespace
}  // namespace glarelab::analysis

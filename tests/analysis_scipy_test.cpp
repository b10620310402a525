// Cross-check with SciPy (Debian's python3-scipy): /usr/bin/python3 reads the exported
// trials.csv, recomputes the forced-choice chi-square and binomial tests and the paired t-tests
// of the adjustments, and the results must agree to 1e-9.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "analysis/analysis_report.h"
#include "analysis/tidy_csv.h"
#include "tests/analysis_synthetic.h"
#include "tests/scratch_dir.h"
#include "tests/scipy_support.h"

namespace glarelab::analysis {
namespace {

constexpr const char* kScript = R"py(
import csv, sys
from collections import defaultdict
from scipy import stats
rows = list(csv.DictReader(open(sys.argv[1], newline='')))
dyn = sum(1 for r in rows if r['procedure'] == 'forced_choice' and r['condition_' + r['response']] == 'dynamic')
sta = sum(1 for r in rows if r['procedure'] == 'forced_choice' and r['condition_' + r['response']] == 'static')
print('chi2 %.17g %.17g' % tuple(stats.chisquare([dyn, sta])))
print('binom %.17g' % stats.binomtest(max(dyn, sta), dyn + sta, 0.5).pvalue)
cells = defaultdict(list)
for r in rows:
    if r['procedure'] == 'adjustment':
        cells[(r['participant'], r['condition_glare'])].append(float(r['intensity']))
parts = sorted({p for p, _ in cells})
mean = lambda v: sum(v) / len(v)
for a, b in [('control', 'static'), ('control', 'dynamic'), ('static', 'dynamic')]:
    x = [mean(cells[(p, a)]) for p in parts]
    y = [mean(cells[(p, b)]) for p in parts]
    t = stats.ttest_rel(x, y)
    print('t %s %s %.17g %.17g' % (a, b, t.statistic, t.pvalue))
)py";

using test::run_python;
using test::scipy_available;

TEST(AnalysisScipy, ChiSquareBinomialAndPairedTMatchScipyOnExportedCsv) {
  std::string why;
  if (!scipy_available(why)) GTEST_SKIP() << why;
  const test::ScratchDir dir;
  const std::string path = dir.file("scipy.db");
  {
    ResultStore store(path);
    const char* glare[] = {"control", "static", "dynamic"};
    for (int p = 0; p < 5; ++p) {
      const auto id = store.begin_session(test::synthetic_session("P" + std::to_string(p)));
      std::vector<test::TrialSpec> specs;
      for (int i = 0; i < 30; ++i) {
        // A condition with a comma and quotes in a field exercises the CSV quoting on the way.
        auto spec = test::preference_trial("Gem, \\\"night\\\"", "brighter", i % 2 == 0, (i * 7 + p) % 10 < 7 ? "dynamic" : "static");
        specs.push_back(spec);
      }
      for (int g = 0; g < 3; ++g) {
        for (int r = 0; r < 2; ++r) {
          const double value = 100.0 + 7.3 * g * (1 + 0.2 * p) + 3.1 * r + 1.7 * ((p * 3 + g) % 4);
          specs.push_back({"adjustment", std::string("{\"glare\":\"") + glare[g] + "\"}", "", {}, value, "", {}});
        }
      }
      test::commit_trials(store, id, specs);
      store.finish_session(id, "completed");
    }
  }
  AnalysisOptions options;
  options.bootstrap_samples = 0;
  const AnalysisReport report = analyse(load_databases({path}), options);
  write_tidy_csv(report.data, dir.path().string());
  const std::string output = run_python(dir.write("check.py", kScript), dir.file("trials.csv"));

  ASSERT_EQ(report.forced_choice.pooled.size(), 1u);
  const PairPreference& pooled = report.forced_choice.pooled[0];
  std::istringstream lines(output);
  std::string tag;
  double chi2 = 0.0, chi2_p = 0.0, binom_p = 0.0;
  ASSERT_TRUE(lines >> tag >> chi2 >> chi2_p && tag == "chi2") << output;
  ASSERT_TRUE(lines >> tag >> binom_p && tag == "binom") << output;
  EXPECT_NEAR(pooled.chi_square.statistic, chi2, 1e-9);
  EXPECT_NEAR(pooled.chi_square.p_value, chi2_p, 1e-9);
  EXPECT_NEAR(pooled.binomial.p_value, binom_p, 1e-9);
  ASSERT_EQ(report.adjustments.paired.size(), 3u);
  for (const PairedComparison& paired : report.adjustments.paired) {
    std::string a, b;
    double t = 0.0, p = 0.0;
    ASSERT_TRUE(lines >> tag >> a >> b >> t >> p && tag == "t") << output;
    EXPECT_EQ(paired.condition_a, a);
    EXPECT_EQ(paired.condition_b, b);
    ASSERT_TRUE(paired.t_test.ok()) << paired.t_test.unavailable;
    EXPECT_NEAR(paired.t_test.statistic, t, 1e-9 * std::max(1.0, std::abs(t)));
    EXPECT_NEAR(paired.t_test.p_value, p, 1e-9);
  }
}

}  // namespace
}  // namespace glarelab::analysis

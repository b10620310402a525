// Post-hoc pairwise signed-rank tests with Holm's adjustment after a significant Friedman test
// (analysis/rating_post_hoc.h): Holm on a vector worked by hand, and on a rating database the
// exported trials.csv recomputed by SciPy: scipy.stats.wilcoxon per pair (the method chosen by
// WilcoxonMethod::automatic's rule) and Holm's step-down adjustment written out in the script.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include "analysis/analysis_report.h"
#include "analysis/rating_post_hoc.h"
#include "analysis/report_output.h"
#include "analysis/tidy_csv.h"
#include "tests/analysis_synthetic.h"
#include "tests/scratch_dir.h"
#include "tests/scipy_support.h"

namespace glarelab::analysis {
namespace {

// Sorted: 0.005 x 4 = 0.02, 0.01 x 3 = 0.03, 0.03 x 2 = 0.06, 0.04 x 1 = 0.04 -> 0.06 (the
// step-down maximum); 0.4 x 1 above 1 is capped. In the given order:
TEST(AnalysisRatingPostHoc, HolmAdjustmentWorkedByHand) {
  const std::vector<double> adjusted = holm_adjusted_p({0.01, 0.04, 0.03, 0.005});
  ASSERT_EQ(adjusted.size(), 4u);
  EXPECT_DOUBLE_EQ(adjusted[0], 0.03);
  EXPECT_DOUBLE_EQ(adjusted[1], 0.06);
  EXPECT_DOUBLE_EQ(adjusted[2], 0.06);
  EXPECT_DOUBLE_EQ(adjusted[3], 0.02);
  const std::vector<double> capped = holm_adjusted_p({0.3, 0.4});
  EXPECT_DOUBLE_EQ(capped[0], 0.6);
  EXPECT_DOUBLE_EQ(capped[1], 0.6);
  EXPECT_TRUE(holm_adjusted_p({}).empty());
}

TEST(AnalysisRatingPostHoc, OnlyASignificantFriedmanTestOpensThePairs) {
  const std::vector<std::vector<double>> scores = {{1, 2, 3}, {2, 3, 5}, {1, 3, 6}};
  EXPECT_TRUE(rating_post_hoc({"a", "b", "c"}, scores, 0.051).empty());
  const std::vector<RatingPairTest> pairs = rating_post_hoc({"a", "b", "c"}, scores, 0.05);
  ASSERT_EQ(pairs.size(), 3u);
  EXPECT_EQ(pairs[0].first + "-" + pairs[0].second, "a-b");
  EXPECT_EQ(pairs[1].first + "-" + pairs[1].second, "a-c");
  EXPECT_EQ(pairs[2].first + "-" + pairs[2].second, "b-c");
  // Three participants, every difference of one sign and distinct |d| in a-c (2, 3, 5): T = 0,
  // exact two-sided p = 2 x 1/8; a-b has tied |d| (1, 1, 2): normal approximation.
  EXPECT_FALSE(pairs[0].wilcoxon.exact);
  EXPECT_TRUE(pairs[1].wilcoxon.exact);
  EXPECT_DOUBLE_EQ(pairs[1].wilcoxon.statistic, 0.0);
  EXPECT_DOUBLE_EQ(pairs[1].wilcoxon.p_value, 0.25);
}

constexpr const char* kScript = R"py(
import csv, sys, warnings
from collections import defaultdict
import numpy as np
from scipy import stats
warnings.simplefilter('ignore')
rows = [r for r in csv.DictReader(open(sys.argv[1], newline='')) if r['procedure'] == 'rating']
conditions, participants, cells = [], [], defaultdict(list)
for r in rows:
    k, p = r['condition_name'], r['participant']
    if k not in conditions: conditions.append(k)
    if p not in participants: participants.append(p)
    cells[(k, p)].append(float(r['response']))
cols = [[np.mean(cells[(k, p)]) for p in participants] for k in conditions]
print('friedman %.17g' % stats.friedmanchisquare(*cols).pvalue)
results = []
for i in range(len(conditions)):
    for j in range(i + 1, len(conditions)):
        d = np.array(cols[i]) - np.array(cols[j])
        ad = np.abs(d)
        exact = len(d) <= 50 and not np.any(d == 0) and len(np.unique(ad)) == len(ad)
        res = stats.wilcoxon(cols[i], cols[j], method='exact' if exact else 'approx')
        results.append([conditions[i], conditions[j], res.statistic, res.pvalue])
# Holm (1979) by hand: sorted ascending, (m - rank) p, running maximum, capped at 1.
m = len(results)
order = sorted(range(m), key=lambda r: results[r][3])
running = 0.0
for rank, r in enumerate(order):
    running = max(running, (m - rank) * results[r][3])
    results[r].append(min(1.0, running))
for first, second, t, p, holm in results:
    print('%s %s %.17g %.17g %.17g' % (first, second, t, p, holm))
)py";

// Ten participants rate four conditions on one category: a clear order of the first three
// (Friedman p far below 0.05) and a fourth close to the third (differences 0, +-1), with tied and
// zero differences, so every pair goes to the tie-corrected approximation.
std::string post_hoc_database(const test::ScratchDir& dir) {
  const std::string path = dir.file("post_hoc.db");
  ResultStore store(path);
  const int ratings[4][10] = {{1, 2, 1, 3, 2, 1, 2, 2, 1, 3},
                              {3, 3, 2, 4, 4, 2, 3, 5, 2, 4},
                              {5, 4, 4, 6, 5, 5, 4, 6, 5, 5},
                              {5, 5, 4, 6, 6, 4, 5, 6, 5, 6}};
  const char* names[4] = {"real_lamp", "standard", "glare", "full"};
  for (int p = 0; p < 10; ++p) {
    const auto id = store.begin_session(test::synthetic_session("P" + std::to_string(p + 1), 20 + p));
    std::vector<test::TrialSpec> specs;
    for (int k = 0; k < 4; ++k)
      specs.push_back({"rating", std::string("{\"name\":\"") + names[k] + "\",\"category\":\"overall\"}",
                       std::to_string(ratings[k][p]), {}, {}, "", {}});
    test::commit_trials(store, id, specs);
    store.finish_session(id, "completed");
  }
  return path;
}

TEST(AnalysisRatingPostHoc, PairsAndHolmMatchScipyOnExportedCsv) {
  std::string why;
  if (!test::scipy_available(why)) GTEST_SKIP() << why;
  const test::ScratchDir dir;
  AnalysisOptions options;
  options.bootstrap_samples = 0;
  const AnalysisReport report = analyse(load_databases({post_hoc_database(dir)}), options);
  write_report(report, dir.path().string());
  const std::string output = test::run_python(dir.write("check.py", kScript), dir.file("trials.csv"));

  ASSERT_EQ(report.ratings.comparisons.size(), 1u);
  const RatingComparison& c = report.ratings.comparisons[0];
  ASSERT_TRUE(c.friedman && c.friedman->ok());
  std::istringstream lines(output);
  std::string word;
  double friedman_p = 0.0;
  ASSERT_TRUE(lines >> word >> friedman_p) << output;
  EXPECT_NEAR(c.friedman->p_value, friedman_p, 1e-12);
  EXPECT_LT(friedman_p, 0.05);
  ASSERT_EQ(c.post_hoc.size(), 6u);
  int below = 0;
  for (const RatingPairTest& pair : c.post_hoc) {
    std::string first, second;
    double statistic = 0.0, p = 0.0, holm = 0.0;
    ASSERT_TRUE(lines >> first >> second >> statistic >> p >> holm) << output;
    EXPECT_EQ(pair.first + " " + pair.second, first + " " + second);
    ASSERT_TRUE(pair.wilcoxon.ok()) << pair.wilcoxon.unavailable;
    EXPECT_FALSE(pair.wilcoxon.exact);
    EXPECT_NEAR(pair.wilcoxon.statistic, statistic, 1e-9) << first << " " << second;
    EXPECT_NEAR(pair.wilcoxon.p_value, p, 1e-9) << first << " " << second;
    EXPECT_NEAR(pair.p_holm, holm, 1e-9) << first << " " << second;
    EXPECT_GE(pair.p_holm, pair.wilcoxon.p_value);
    below += pair.p_holm <= 0.05;
  }
  EXPECT_GT(below, 0) << "the data were built so that some pairs differ after the adjustment";
  EXPECT_LT(below, 6) << "and so that some do not (glare against full)";
  // rating_post_hoc.csv: a header and a row per pair; the terminal states each pair.
  const std::string csv = test::read_bytes(dir.file("rating_post_hoc.csv"));
  EXPECT_EQ(csv.substr(0, csv.find('\r')),
            "category,first,second,participants,zero_differences,statistic,z,p_value,p_holm,method,not_computed");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 7);
  const std::string summary = render_terminal_summary(report);
  EXPECT_NE(summary.find("rating post hoc overall, real_lamp vs standard: Wilcoxon T = "), std::string::npos) << summary;
  EXPECT_NE(summary.find(", Holm p = "), std::string::npos) << summary;
}

}  // namespace
}  // namespace glarelab::analysis

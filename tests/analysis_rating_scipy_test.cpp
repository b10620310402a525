// The rating analysis against SciPy (Debian's python3-scipy, called as /usr/bin/python3): the
// script reads the exported trials.csv, pairs the ratings itself (same participant, same
// category; repetitions averaged), and runs scipy.stats.wilcoxon and friedmanchisquare. The
// statistics and p-values must agree to 1e-9.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "analysis/analysis_report.h"
#include "analysis/rank_tests.h"
#include "analysis/report_output.h"
#include "analysis/tidy_csv.h"
#include "tests/analysis_synthetic.h"
#include "tests/scratch_dir.h"
#include "tests/scipy_support.h"

namespace glarelab::analysis {
namespace {

// For two conditions the script chooses the method by the rule of WilcoxonMethod::automatic
// (exact without zeros or tied |d| for <= 50 pairs, else the normal approximation) and passes it
// to SciPy; it also prints SciPy's own default ("auto") p-value, which equals the exact one when
// there are no ties, and the continuity-corrected approximation.
constexpr const char* kScript = R"py(
import csv, sys, warnings
from collections import defaultdict
import numpy as np
from scipy import stats
warnings.simplefilter('ignore')
rows = [r for r in csv.DictReader(open(sys.argv[1], newline='')) if r['procedure'] == 'rating']
categories, conditions, participants = [], defaultdict(list), []
cells = defaultdict(list)
for r in rows:
    c, k, p = r['condition_category'], r['condition_name'], r['participant']
    if c not in categories: categories.append(c)
    if k not in conditions[c]: conditions[c].append(k)
    if p not in participants: participants.append(p)
    cells[(c, k, p)].append(float(r['response']))
for i, c in enumerate(categories):
    ks = conditions[c]
    complete = [p for p in participants if all((c, k, p) in cells for k in ks)]
    cols = [[np.mean(cells[(c, k, p)]) for p in complete] for k in ks]
    if len(ks) == 2:
        d = np.array(cols[0]) - np.array(cols[1])
        ad = np.abs(d)
        exact = len(d) <= 50 and not np.any(d == 0) and len(np.unique(ad)) == len(ad)
        method = 'exact' if exact else 'approx'
        res = stats.wilcoxon(cols[0], cols[1], method=method)
        auto = stats.wilcoxon(cols[0], cols[1])
        corr = stats.wilcoxon(cols[0], cols[1], method='approx', correction=True)
        print('%d wilcoxon %s %d %.17g %.17g %.17g %.17g' % (i, method, len(complete), res.statistic, res.pvalue,
                                                             auto.pvalue, corr.pvalue))
    else:
        res = stats.friedmanchisquare(*cols)
        n, k = len(complete), len(ks)
        print('%d friedman %d %d %.17g %.17g %.17g' % (i, n, k, res.statistic, res.pvalue, res.statistic / (n * (k - 1))))
)py";

using test::run_python;
using test::scipy_available;

test::TrialSpec rating(const std::string& condition, const std::string& category, int value) {
  return {"rating", "{\"name\":\"" + condition + "\",\"category\":\"" + category + "\"}", std::to_string(value), {}, {}, "",
          {}};
}

// Nine participants. "glare, appearance" (a comma: quoted in the CSV): A and B with zero and tied
// differences. "movement": A and B rated twice each, whose means differ by 0.5, -1, 1.5, 2, 2.5,
// 3, -3.5, 4, 4.5 (distinct, none zero). "adaptation": A, B and C with ties within participants;
// P9 never rates C and is left out.
std::string rating_database(const test::ScratchDir& dir) {
  const std::string path = dir.file("ratings.db");
  ResultStore store(path);
  const int tie_a[] = {5, 4, 6, 3, 6, 7, 4, 5, 2};
  const int tie_b[] = {4, 3, 5, 4, 4, 5, 4, 3, 2};
  const int sum_difference[] = {1, -2, 3, 4, 5, 6, -7, 8, 9};
  const int three[9][3] = {{2, 4, 6}, {3, 3, 5}, {1, 5, 5}, {4, 6, 7}, {2, 2, 2}, {5, 3, 6}, {1, 4, 7}, {3, 5, 4}, {6, 6, 7}};
  for (int p = 0; p < 9; ++p) {
    const auto id = store.begin_session(test::synthetic_session("P" + std::to_string(p + 1), 10 + p));
    std::vector<test::TrialSpec> specs;
    specs.push_back(rating("A", "glare, appearance", tie_a[p]));
    specs.push_back(rating("B", "glare, appearance", tie_b[p]));
    // Sums of two ratings: B = 2 + 2 (5 + 5 when A's sum must be small), A = B's sum + difference.
    const int b_sum = sum_difference[p] < -3 ? 10 : 4;
    const int a_sum = b_sum + sum_difference[p];
    const int a_first = std::min(7, a_sum - 1);
    specs.push_back(rating("A", "movement", a_first));
    specs.push_back(rating("B", "movement", b_sum / 2));
    specs.push_back(rating("A", "movement", a_sum - a_first));
    specs.push_back(rating("B", "movement", b_sum / 2));
    for (int c = 0; c < (p == 8 ? 2 : 3); ++c) specs.push_back(rating(std::string(1, static_cast<char>('A' + c)), "adaptation", three[p][c]));
    test::commit_trials(store, id, specs);
    store.finish_session(id, "completed");
  }
  return path;
}

TEST(AnalysisRatingScipy, SignedRankAndFriedmanMatchScipyOnExportedCsv) {
  std::string why;
  if (!scipy_available(why)) GTEST_SKIP() << why;
  const test::ScratchDir dir;
  AnalysisOptions options;
  options.bootstrap_samples = 0;
  const AnalysisReport report = analyse(load_databases({rating_database(dir)}), options);
  write_tidy_csv(report.data, dir.path().string());
  const std::string output = run_python(dir.write("check.py", kScript), dir.file("trials.csv"));

  const RatingAnalysis& ratings = report.ratings;
  ASSERT_EQ(ratings.comparisons.size(), 3u);
  EXPECT_EQ(ratings.comparisons[0].category, "glare, appearance");
  std::istringstream lines(output);
  for (std::size_t i = 0; i < 3; ++i) {
    const RatingComparison& c = ratings.comparisons[i];
    std::size_t index = 0;
    std::string test;
    ASSERT_TRUE(lines >> index >> test) << output;
    ASSERT_EQ(index, i) << output;
    if (test == "wilcoxon") {
      std::string method;
      std::size_t n = 0;
      double statistic = 0.0, p = 0.0, p_auto = 0.0, p_corrected = 0.0;
      ASSERT_TRUE(lines >> method >> n >> statistic >> p >> p_auto >> p_corrected) << output;
      ASSERT_TRUE(c.wilcoxon.has_value()) << c.category;
      const WilcoxonSignedRank& w = *c.wilcoxon;
      ASSERT_TRUE(w.ok()) << w.unavailable;
      EXPECT_EQ(w.pairs, n);
      EXPECT_EQ(w.exact, method == "exact") << c.category;
      EXPECT_NEAR(w.statistic, statistic, 1e-9) << c.category;
      EXPECT_NEAR(w.p_value, p, 1e-9) << c.category;
      if (w.exact) {
        EXPECT_NEAR(w.p_value, p_auto, 1e-9) << "SciPy's default agrees without ties";
      }
      std::vector<double> first, second;
      for (const auto& row : c.scores) {
        first.push_back(row[0]);
        second.push_back(row[1]);
      }
      const WilcoxonSignedRank corrected = wilcoxon_signed_rank(first, second, WilcoxonMethod::normal, true);
      EXPECT_NEAR(corrected.p_value, p_corrected, 1e-9) << c.category;
    } else {
      ASSERT_EQ(test, "friedman") << output;
      std::size_t n = 0, k = 0;
      double chi2 = 0.0, p = 0.0, w = 0.0;
      ASSERT_TRUE(lines >> n >> k >> chi2 >> p >> w) << output;
      ASSERT_TRUE(c.friedman.has_value()) << c.category;
      const FriedmanTest& f = *c.friedman;
      ASSERT_TRUE(f.ok()) << f.unavailable;
      EXPECT_EQ(f.subjects, n);
      EXPECT_EQ(f.conditions, k);
      EXPECT_NEAR(f.chi_square, chi2, 1e-9);
      EXPECT_NEAR(f.p_value, p, 1e-9);
      EXPECT_NEAR(f.kendall_w, w, 1e-9);
    }
  }
  // What the data were built to exercise.
  EXPECT_FALSE(ratings.comparisons[0].wilcoxon->exact);
  EXPECT_EQ(ratings.comparisons[0].wilcoxon->zero_differences, 2u);
  EXPECT_TRUE(ratings.comparisons[1].wilcoxon->exact);
  EXPECT_EQ(ratings.comparisons[1].scores[0], (std::vector<double>{2.5, 2.0}));
  EXPECT_LT(ratings.comparisons[2].friedman->tie_correction, 1.0);
  EXPECT_EQ(ratings.comparisons[2].left_out, (std::vector<std::string>{"P9"}));

  // The terminal summary states each test with its method, zeros and who was left out.
  const std::string summary = render_terminal_summary(report);
  for (const char* expected :
       {"rating test glare, appearance (A vs B): Wilcoxon signed-rank T = ", "normal approximation z = ",
        "; 9 participants, 2 zero differences discarded", "rating test movement (A vs B): Wilcoxon signed-rank T = ",
        "), exact p = ", "rating test adaptation (A vs B vs C): Friedman chi2(2) = ", "Kendall's W = ",
        "; 8 participants, tie correction ", "; left out (not every condition rated): P9"}) {
    EXPECT_NE(summary.find(expected), std::string::npos) << expected << "\n" << summary;
  }
}

}  // namespace
}  // namespace glarelab::analysis

// examples/luidolt_ratings.toml run offscreen by three simulated participants (each its own
// participant code and seed) into one database, then `glarelab analyze`: every one of the six
// categories gets its distributions, its figure and a Friedman test across the four conditions
// (the real lamp and three simulations) on the three participants' paired ratings. (Three, not
// Luidolt's five: each run renders 24 trials, 18 of them images.) The example is copied with one
// frame per stimulus (tests/example_copies.h): the simulated observer's ratings do not depend on
// the frames (the same seed gives the same trials and answers either way), and a run takes about
// 1.3 CPU-s instead of 5.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "cli_process.h"
#include "example_copies.h"

namespace glarelab {
namespace {

const std::vector<std::string> kCategories = {"glare appearance", "glare movement", "eye adaptation",
                                              "visual acuity",    "scotopic vision", "overall"};

std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::vector<std::string> fields;
    std::string field;
    std::istringstream cells(line);
    while (std::getline(cells, field, ',')) fields.push_back(field);
    if (!line.empty() && line.back() == ',') fields.emplace_back();
    rows.push_back(fields);
  }
  return rows;
}

TEST(AnalysisRatingExample, LuidoltRatingsByThreeParticipantsGetPerCategoryTests) {
  const test::ScratchDir scratch;
  const auto db = scratch.path() / "luidolt.db";
  const auto file = test::examples_with_frames(scratch.path(), 1) / "luidolt_ratings.toml";
  for (int p = 1; p <= 3; ++p) {
    const auto run = test::run_glarelab({"run", file.string(),
                                         "--display", "offscreen", "--observer", "simulated", "--participant",
                                         "P" + std::to_string(p), "--seed", std::to_string(100 + p), "--db", db.string()},
                                        scratch.path());
    ASSERT_EQ(run.exit_code, 0) << run.output;
  }
  const auto out = scratch.path() / "analysis";
  const auto analysis = test::run_glarelab({"analyze", db.string(), "--out", out.string()}, scratch.path());
  ASSERT_EQ(analysis.exit_code, 0) << analysis.output;
  const std::string& summary = analysis.output;
  for (const std::string condition : {"real_lamp", "standard", "glare", "full"})
    EXPECT_NE(summary.find("rating " + condition + ": 18 answers"), std::string::npos) << summary;
  for (const std::string& category : kCategories) {
    const std::string line = "rating test " + category + " (real_lamp vs standard vs glare vs full): Friedman chi2(3) = ";
    const auto at = summary.find(line);
    ASSERT_NE(at, std::string::npos) << summary;
    EXPECT_NE(summary.substr(at, summary.find('\n', at) - at).find("; 3 participants"), std::string::npos) << summary;
  }
  for (int f = 1; f <= 6; ++f)
    EXPECT_TRUE(std::filesystem::exists(out / "figures" / ("rating_" + std::to_string(f) + ".svg"))) << f;
  const std::string html = test::read_bytes((out / "report.html").string());
  EXPECT_NE(html.find("Kendall&#39;s W = "), std::string::npos);

  // ratings.csv: 6 categories x 4 conditions, a column per point of the stored 7-point scale
  // (Luidolt 2020, 7.2.1), and every cell holds the three participants' answers.
  const auto ratings = csv_rows(test::read_bytes((out / "ratings.csv").string()));
  ASSERT_EQ(ratings.size(), 25u);
  EXPECT_EQ(ratings[0], (std::vector<std::string>{"category", "condition", "answers", "mean", "median", "answers_1",
                                                   "answers_2", "answers_3", "answers_4", "answers_5", "answers_6",
                                                   "answers_7"}));
  for (std::size_t r = 1; r < ratings.size(); ++r) {
    ASSERT_EQ(ratings[r].size(), 12u);
    EXPECT_EQ(ratings[r][2], "3");
    long sum = 0;
    for (std::size_t c = 5; c < 12; ++c) sum += std::stol(ratings[r][c]);
    EXPECT_EQ(sum, 3) << ratings[r][0] << " " << ratings[r][1];
  }
  // rating_tests.csv: a Friedman row per category with chi2, df 3, p and W = chi2 / (n (k - 1))
  // = chi2 / (3 * 3).
  const auto tests = csv_rows(test::read_bytes((out / "rating_tests.csv").string()));
  ASSERT_EQ(tests.size(), 7u);
  double chi_square_sum = 0.0;
  for (std::size_t r = 1; r < tests.size(); ++r) {
    ASSERT_EQ(tests[r].size(), 12u);
    EXPECT_EQ(tests[r][0], kCategories[r - 1]);
    EXPECT_EQ(tests[r][2], "friedman");
    EXPECT_EQ(tests[r][3], "3");
    EXPECT_EQ(tests[r][6], "3");
    const double chi2 = std::stod(tests[r][5]);
    EXPECT_NEAR(std::stod(tests[r][9]), chi2 / 9.0, 1e-12);
    EXPECT_GE(std::stod(tests[r][8]), 0.0);
    EXPECT_LE(std::stod(tests[r][8]), 1.0);
    chi_square_sum += chi2;
  }
  // The simulated means 6.6 (real lamp), 3.0, 4.0 and 5.0 (noise sd 0.7) order the conditions
  // for most participants: the mean statistic lies far above its null expectation, df = 3, near
  // its largest value n (k - 1) = 9 (7.9 for these seeds).
  EXPECT_GT(chi_square_sum / 6.0, 6.0);

  // Post hoc (analysis/rating_post_hoc.h): each category whose Friedman p is at most 0.05 gets its
  // 6 pairs of the 4 conditions, in rating_post_hoc.csv and the summary, Holm p >= the pair's p.
  std::size_t significant = 0;
  for (std::size_t r = 1; r < tests.size(); ++r) {
    if (std::stod(tests[r][8]) > 0.05) continue;
    ++significant;
    EXPECT_NE(summary.find("rating post hoc " + tests[r][0] + ", real_lamp vs standard: Wilcoxon T = "), std::string::npos)
        << summary;
  }
  if (significant > 0) {
    const auto pairs = csv_rows(test::read_bytes((out / "rating_post_hoc.csv").string()));
    ASSERT_EQ(pairs.size(), 1 + 6 * significant);
    for (std::size_t r = 1; r < pairs.size(); ++r) {
      ASSERT_EQ(pairs[r].size(), 11u);
      EXPECT_GE(std::stod(pairs[r][8]), std::stod(pairs[r][7])) << pairs[r][0] << " " << pairs[r][1] << " " << pairs[r][2];
    }
  } else {
    EXPECT_FALSE(std::filesystem::exists(out / "rating_post_hoc.csv"));
  }

  // SciPy recomputes every category's Friedman test from trials.csv, in the conditions' order.
  if (std::system("/usr/bin/python3 -c 'import scipy.stats' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "SciPy is missing for /usr/bin/python3 (install python3-scipy): the statistics were not cross-checked";
  const std::string script = scratch.write("friedman.py", R"py(
import csv, sys
import numpy as np
from scipy import stats
rows = [r for r in csv.DictReader(open(sys.argv[1], newline='')) if r['procedure'] == 'rating']
for test in csv.DictReader(open(sys.argv[2], newline='')):
    c, ks = test['category'], test['conditions'].split(';')
    cells = {}
    for r in rows:
        if r['condition_category'] == c:
            cells.setdefault((r['participant'], r['condition_name']), []).append(float(r['response']))
    ps = sorted({p for p, _ in cells if all((p, k) in cells for k in ks)})
    res = stats.friedmanchisquare(*[[np.mean(cells[(p, k)]) for p in ps] for k in ks])
    print('%.17g %.17g' % (res.statistic, res.pvalue))
)py");
  FILE* pipe = ::popen(("/usr/bin/python3 " + script + " " + (out / "trials.csv").string() + " " +
                        (out / "rating_tests.csv").string() + " 2>&1")
                           .c_str(),
                       "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buffer[256];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  ::pclose(pipe);
  std::istringstream lines(output);
  for (std::size_t r = 1; r < tests.size(); ++r) {
    double chi2 = 0.0, p = 0.0;
    ASSERT_TRUE(lines >> chi2 >> p) << output;
    EXPECT_NEAR(std::stod(tests[r][5]), chi2, 1e-9) << tests[r][0];
    EXPECT_NEAR(std::stod(tests[r][8]), p, 1e-9) << tests[r][0];
  }
}

}  // namespace
}  // namespace glarelab

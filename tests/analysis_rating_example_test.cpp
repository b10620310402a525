// examples/luidolt_ratings.toml run offscreen by five simulated participants (each its own
// participant code and seed) into one database, then `glarelab analyze`: every one of the six
// categories gets its distributions, its figure and a Friedman test across the three conditions
// on the five participants' paired ratings.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include "cli_process.h"

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

TEST(AnalysisRatingExample, LuidoltRatingsByFiveParticipantsGetPerCategoryTests) {
  const test::ScratchDir scratch;
  const auto db = scratch.path() / "luidolt.db";
  for (int p = 1; p <= 5; ++p) {
    const auto run = test::run_glarelab({"run", std::string(GLARELAB_SOURCE_DIR) + "/examples/luidolt_ratings.toml",
                                         "--display", "offscreen", "--observer", "simulated", "--participant",
                                         "P" + std::to_string(p), "--seed", std::to_string(100 + p), "--db", db.string()},
                                        scratch.path());
    ASSERT_EQ(run.exit_code, 0) << run.output;
  }
  const auto out = scratch.path() / "analysis";
  const auto analysis = test::run_glarelab({"analyze", db.string(), "--out", out.string()}, scratch.path());
  ASSERT_EQ(analysis.exit_code, 0) << analysis.output;
  const std::string& summary = analysis.output;
  for (const std::string condition : {"control", "static", "dynamic"})
    EXPECT_NE(summary.find("rating " + condition + ": 30 answers"), std::string::npos) << summary;
  for (const std::string& category : kCategories) {
    const std::string line = "rating test " + category + " (control vs static vs dynamic): Friedman chi2(2) = ";
    const auto at = summary.find(line);
    ASSERT_NE(at, std::string::npos) << summary;
    EXPECT_NE(summary.substr(at, summary.find('\n', at) - at).find("; 5 participants"), std::string::npos) << summary;
  }
  for (int f = 1; f <= 6; ++f)
    EXPECT_TRUE(std::filesystem::exists(out / "figures" / ("rating_" + std::to_string(f) + ".svg"))) << f;
  const std::string html = test::read_bytes((out / "report.html").string());
  EXPECT_NE(html.find("Kendall&#39;s W = "), std::string::npos);

  // ratings.csv: 6 categories x 3 conditions, a column per point of the stored 5-point scale,
  // and every cell holds the five participants' answers.
  const auto ratings = csv_rows(test::read_bytes((out / "ratings.csv").string()));
  ASSERT_EQ(ratings.size(), 19u);
  EXPECT_EQ(ratings[0], (std::vector<std::string>{"category", "condition", "answers", "mean", "median", "answers_1",
                                                   "answers_2", "answers_3", "answers_4", "answers_5"}));
  for (std::size_t r = 1; r < ratings.size(); ++r) {
    ASSERT_EQ(ratings[r].size(), 10u);
    EXPECT_EQ(ratings[r][2], "5");
    long sum = 0;
    for (std::size_t c = 5; c < 10; ++c) sum += std::stol(ratings[r][c]);
    EXPECT_EQ(sum, 5) << ratings[r][0] << " " << ratings[r][1];
  }
  // rating_tests.csv: a Friedman row per category with chi2, df 2, p and W = chi2 / (5 * 2).
  const auto tests = csv_rows(test::read_bytes((out / "rating_tests.csv").string()));
  ASSERT_EQ(tests.size(), 7u);
  double chi_square_sum = 0.0;
  for (std::size_t r = 1; r < tests.size(); ++r) {
    ASSERT_EQ(tests[r].size(), 12u);
    EXPECT_EQ(tests[r][0], kCategories[r - 1]);
    EXPECT_EQ(tests[r][2], "friedman");
    EXPECT_EQ(tests[r][3], "5");
    EXPECT_EQ(tests[r][6], "2");
    const double chi2 = std::stod(tests[r][5]);
    EXPECT_NEAR(std::stod(tests[r][9]), chi2 / 10.0, 1e-12);
    EXPECT_GE(std::stod(tests[r][8]), 0.0);
    EXPECT_LE(std::stod(tests[r][8]), 1.0);
    chi_square_sum += chi2;
  }
  // The simulated means are 2.0, 3.0 and 4.2 with noise sd 0.7: the participants mostly agree
  // on the order, so the statistics are far from zero.
  EXPECT_GT(chi_square_sum / 6.0, 4.0);
}

}  // namespace
}  // namespace glarelab

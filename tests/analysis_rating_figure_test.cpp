// The rating figures (Luidolt 2020, Figs. 7.2-7.7): per category, a bar per condition stacked by
// answer value, the median marked. The SVG is read back (bars, legend, median dots) and must give
// the counts the synthetic database was built with; the report renders in headless Chromium.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <regex>

#include "analysis/analysis_report.h"
#include "analysis/report_output.h"
#include "analysis/svg_plot.h"
#include "core/png_io.h"
#include "tests/analysis_synthetic.h"
#include "tests/headless_chromium.h"
#include "tests/scratch_dir.h"

namespace glarelab::analysis {
namespace {

// answers[category][condition]: one rating per participant (participant i gives the i-th).
const std::map<std::string, std::map<std::string, std::vector<int>>> kAnswers = {
    {"appearance", {{"A", {1, 2, 2, 3, 5, 7}}, {"B", {4, 4, 4, 5, 6, 6}}, {"C", {7, 7, 6, 7, 5, 7}}}},
    {"overall", {{"A", {3, 3, 3, 3, 3, 3}}, {"B", {1, 2, 3, 4, 5, 6}}, {"C", {2, 2, 5, 5, 5, 6}}}}};

std::string figure_database(const test::ScratchDir& dir) {
  const std::string path = dir.file("figure.db");
  ResultStore store(path);
  for (int p = 0; p < 6; ++p) {
    SessionRecord session = test::synthetic_session("P" + std::to_string(p + 1));
    // A 9-point scale: 8 and 9 are never chosen but belong in the figure's legend.
    session.config = "[experiment]\nname = \"synthetic\"\n[procedure]\ntype = \"rating\"\nscale_points = 9\n";
    const auto id = store.begin_session(session);
    std::vector<test::TrialSpec> specs;
    for (const auto& [category, conditions] : kAnswers)
      for (const auto& [condition, values] : conditions)
        specs.push_back({"rating", "{\"name\":\"" + condition + "\",\"category\":\"" + category + "\"}",
                         std::to_string(values[static_cast<std::size_t>(p)]), {}, {}, "", {}});
    test::commit_trials(store, id, specs);
    store.finish_session(id, "completed");
  }
  return path;
}

struct Rect {
  double x, y, width, height;
  std::string fill;
};

std::vector<Rect> rects(const std::string& svg) {
  static const std::regex pattern(
      R"re(<rect x="([0-9.]+)" y="([0-9.]+)" width="([0-9.]+)" height="([0-9.]+)" fill="(#[0-9a-f]{6})"/>)re");
  std::vector<Rect> found;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), pattern); it != std::sregex_iterator(); ++it) {
    found.push_back({std::stod((*it)[1]), std::stod((*it)[2]), std::stod((*it)[3]), std::stod((*it)[4]), (*it)[5]});
  }
  return found;
}

// Legend: colour -> answer value, read from "<rect .../><text ...>answer 7</text>".
std::map<std::string, int> legend(const std::string& svg) {
  static const std::regex pattern(R"re(fill="(#[0-9a-f]{6})"/><text x="[0-9.]+" y="[0-9.]+">answer ([0-9]+)</text>)re");
  std::map<std::string, int> found;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), pattern); it != std::sregex_iterator(); ++it)
    found[(*it)[1]] = std::stoi((*it)[2]);
  return found;
}

const Figure& figure(const AnalysisReport& report, const std::string& stem) {
  for (const Figure& f : report.figures)
    if (f.file_stem == stem) return f;
  throw std::runtime_error("no figure " + stem);
}

TEST(AnalysisRatingFigure, StackedBarsHoldTheCountsAndTheMedianIsMarked) {
  const test::ScratchDir dir;
  AnalysisOptions options;
  options.bootstrap_samples = 0;
  const AnalysisReport report = analyse(load_databases({figure_database(dir)}), options);
  ASSERT_EQ(report.ratings.category_order, (std::vector<std::string>{"appearance", "overall"}));
  ASSERT_EQ(report.ratings.scale.size(), 9u);
  for (std::size_t f = 0; f < 2; ++f) {
    const std::string& category = report.ratings.category_order[f];
    const std::string svg = figure(report, "rating_" + std::to_string(f + 1)).svg;
    EXPECT_NE(svg.find("Ratings: " + category), std::string::npos);
    const std::map<std::string, int> colours = legend(svg);
    ASSERT_EQ(colours.size(), 9u) << "every point of the 9-point scale in the legend";
    // Bars: rects in a legend colour wider than the legend's 10 px swatches, grouped by x.
    std::map<double, std::vector<Rect>> bars;
    for (const Rect& r : rects(svg))
      if (colours.count(r.fill) && r.width > 10.5) bars[r.x].push_back(r);
    ASSERT_EQ(bars.size(), 3u) << svg;
    const auto& conditions = kAnswers.at(category);
    auto condition = conditions.begin();  // A, B, C: left to right
    for (auto& [x, segments] : bars) {
      const std::vector<int>& values = condition->second;
      // Each segment's rect reaches from the axis to the cumulative count up to its value;
      // shortest first, the values must rise, and the steps are the counts.
      std::sort(segments.begin(), segments.end(), [](const Rect& a, const Rect& b) { return a.height < b.height; });
      const double full_px = segments.back().height;
      const double bottom_px = segments.back().y + full_px;
      std::map<int, long> counts;
      double below_px = 0.0;
      int previous = 0;
      for (const Rect& r : segments) {
        const int value = colours.at(r.fill);
        EXPECT_GT(value, previous) << "stacked in scale order";
        previous = value;
        EXPECT_NEAR(r.y + r.height, bottom_px, 0.011) << "every segment rect stands on the axis";
        counts[value] = std::lround(static_cast<double>(values.size()) * (r.height - below_px) / full_px);
        below_px = r.height;
      }
      std::map<int, long> expected;
      for (int v : values) ++expected[v];
      EXPECT_EQ(counts, expected) << category << " " << condition->first;
      // The median's dot at half the answers over the bar's centre.
      std::vector<double> sorted(values.begin(), values.end());
      std::sort(sorted.begin(), sorted.end());
      const double median = 0.5 * (sorted[2] + sorted[3]);
      const double centre_px = x + 0.5 * segments.back().width;
      static const std::regex dot(R"re(<circle cx="([0-9.]+)" cy="([0-9.]+)" r="4.50" fill="#000"/>)re");
      int dots = 0;
      for (auto it = std::sregex_iterator(svg.begin(), svg.end(), dot); it != std::sregex_iterator(); ++it) {
        if (std::abs(std::stod((*it)[1]) - centre_px) > 0.02) continue;
        ++dots;
        EXPECT_NEAR(std::stod((*it)[2]), bottom_px - 0.5 * full_px, 0.011);
      }
      EXPECT_EQ(dots, 1) << "one median dot over the bar at " << centre_px;
      char label[64];
      std::snprintf(label, sizeof label, "%s (%g)</text>", condition->first.c_str(), median);
      EXPECT_NE(svg.find(label), std::string::npos) << label;
      ++condition;
    }
  }
}

// Fig. 7.1: a bar per category and condition whose height is the mean answer, on an axis from 0
// to the scale's top (9): 232 px of plot height for 9 points.
TEST(AnalysisRatingFigure, MeanFigureBarsAreTheMeans) {
  const test::ScratchDir dir;
  AnalysisOptions options;
  options.bootstrap_samples = 0;
  const AnalysisReport report = analyse(load_databases({figure_database(dir)}), options);
  const std::string svg = figure(report, "rating_means").svg;
  std::vector<double> means_from_bars;
  std::vector<double> expected;
  std::size_t c = 0;
  for (const std::string condition : {"A", "B", "C"}) {
    for (const Rect& r : rects(svg))
      if (r.fill == series_colour(c) && r.width > 10.5) means_from_bars.push_back(9.0 * r.height / 232.0);
    for (const std::string category : {"appearance", "overall"}) {
      const std::vector<int>& values = kAnswers.at(category).at(condition);
      double sum = 0.0;
      for (int v : values) sum += v;
      expected.push_back(sum / static_cast<double>(values.size()));
    }
    ++c;
  }
  ASSERT_EQ(means_from_bars.size(), expected.size()) << svg;
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(means_from_bars[i], expected[i], 1e-3) << i;
}

TEST(AnalysisRatingFigure, ReportRendersInHeadlessChromium) {
  const std::string chromium = test::chromium_binary();
  if (chromium.empty()) GTEST_SKIP() << "chromium is not installed (Debian package chromium; scripts/setup.sh installs it)";
  const test::ScratchDir dir;
  AnalysisOptions options;
  options.bootstrap_samples = 0;
  const AnalysisReport report = analyse(load_databases({figure_database(dir)}), options);
  const auto out = dir.path() / "out";
  write_report(report, out.string());
  for (const char* file : {"figures/rating_1.svg", "figures/rating_2.svg", "ratings.csv", "rating_tests.csv"})
    EXPECT_TRUE(std::filesystem::exists(out / file)) << file;
  const std::string screenshot = (dir.path() / "shot.png").string();
  const std::string command = test::headless_chromium_command(chromium, 60, dir.path() / "profile",
                                                              "--screenshot=" + screenshot + " --window-size=1200,3000",
                                                              out / "report.html") +
                              " >" + (dir.path() / "chromium.log").string() + " 2>&1";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(std::filesystem::exists(screenshot))
      << "chromium exit status " << status << ": " << test::read_bytes((dir.path() / "chromium.log").string());
  const ImageRGBA image = read_png_encoded(screenshot);
  // Answers 1 and 7 (two and five of them over both figures): bars of about 66 px by 38 px per
  // answer in their legend colours; nothing else on the page has these colours.
  const std::map<std::string, int> colours = legend(figure(report, "rating_1").svg);
  for (const auto& [hex, value] : colours) {
    if (value != 1 && value != 7) continue;
    const double r = std::stoi(hex.substr(1, 2), nullptr, 16) / 255.0;
    const double g = std::stoi(hex.substr(3, 2), nullptr, 16) / 255.0;
    const double b = std::stoi(hex.substr(5, 2), nullptr, 16) / 255.0;
    long count = 0;
    for (int y = 0; y < image.height_px; ++y) {
      for (int x = 0; x < image.width_px; ++x) {
        const float* p = image.pixel(x, y);
        if (std::abs(p[0] - r) < 6.0 / 255 && std::abs(p[1] - g) < 6.0 / 255 && std::abs(p[2] - b) < 6.0 / 255) ++count;
      }
    }
    EXPECT_GT(count, value == 1 ? 2500 : 6000) << "answer " << value << " (" << hex << ")";
  }
}

}  // namespace
}  // namespace glarelab::analysis

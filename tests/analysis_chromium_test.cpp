// The HTML report renders in headless Chromium (Debian's chromium) and its figures are drawn:
// the screenshot holds the figures' series colours, which no other part of the page uses.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "analysis/analysis_report.h"
#include "analysis/report_output.h"
#include "analysis/svg_plot.h"
#include "core/png_io.h"
#include "tests/analysis_synthetic.h"
#include "tests/headless_chromium.h"
#include "tests/scratch_dir.h"

namespace glarelab::analysis {
namespace {


// Pixels within 12/255 of the colour "#rrggbb".
long count_colour(const ImageRGBA& image, const std::string& hex) {
  const double r = std::stoi(hex.substr(1, 2), nullptr, 16) / 255.0;
  const double g = std::stoi(hex.substr(3, 2), nullptr, 16) / 255.0;
  const double b = std::stoi(hex.substr(5, 2), nullptr, 16) / 255.0;
  long count = 0;
  for (int y = 0; y < image.height_px; ++y) {
    for (int x = 0; x < image.width_px; ++x) {
      const float* p = image.pixel(x, y);
      if (std::abs(p[0] - r) < 12.0 / 255 && std::abs(p[1] - g) < 12.0 / 255 && std::abs(p[2] - b) < 12.0 / 255) ++count;
    }
  }
  return count;
}

TEST(AnalysisChromium, ReportRendersWithFiguresDrawn) {
  const std::string chromium = test::chromium_binary();
  if (chromium.empty()) GTEST_SKIP() << "chromium is not installed (Debian package chromium; scripts/setup.sh installs it)";
  const test::ScratchDir dir;
  const std::string path = dir.file("render.db");
  {
    ResultStore store(path);
    for (int p = 0; p < 2; ++p) {
      const auto id = store.begin_session(test::synthetic_session("P" + std::to_string(p)));
      std::vector<test::TrialSpec> specs;
      for (int i = 0; i < 40; ++i) {
        specs.push_back(test::preference_trial(i < 20 ? "Gem" : "Park", "brighter", i % 2 == 0, i % 4 == 3 ? "static" : "dynamic"));
      }
      test::commit_trials(store, id, specs);
      store.finish_session(id, "completed");
    }
  }
  AnalysisOptions options;
  options.bootstrap_samples = 0;
  const AnalysisReport report = analyse(load_databases({path}), options);
  const auto out = dir.path() / "out";
  write_report(report, out.string());
  const std::string screenshot = (dir.path() / "shot.png").string();
  const std::string profile = (dir.path() / "profile").string();
  const std::string command = test::headless_chromium_command(chromium, 60, profile,
                                                              "--screenshot=" + screenshot + " --window-size=1200,2000",
                                                              out / "report.html") +
                              " >" + (dir.path() / "chromium.log").string() + " 2>&1";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(std::filesystem::exists(screenshot))
      << "chromium exit status " << status << ": " << test::read_bytes((dir.path() / "chromium.log").string());
  const ImageRGBA image = read_png_encoded(screenshot);
  EXPECT_EQ(image.width_px, 1200);
  // The forced-choice figure has bars in the first two series colours; a page without
  // figures has none of these pixels.
  EXPECT_GT(count_colour(image, series_colour(0)), 2000);
  EXPECT_GT(count_colour(image, series_colour(1)), 2000);
}

}  // namespace
}  // namespace glarelab::analysis

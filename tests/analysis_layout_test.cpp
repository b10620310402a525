// Figures that lay themselves out (titles, legends and labels never clipped or overlapping):
// the report of every example in examples/ is drawn (tests/example_dry_run.h: the example's own
// procedure answered by its simulated observer, two participants) and every figure is rendered in
// headless Chromium (Debian's chromium), which gives the boxes the browser actually lays out. A
// page holding the figures runs a script that measures, per figure:
//   - every text element's box lies inside the SVG's viewport;
//   - no two text elements' boxes overlap;
//   - the legend's box does not overlap the plotting area (class plot-area) nor any data mark
//     (the circles and rectangles of class data);
//   - every interval (the paths of class data: error bars, caps, arrowheads) lies inside the
//     plotting area;
//   - in the psychometric figures (graded choice, staircases), no two data rings (circles sized by
//     trials) overlap.
// Beside the examples, a `glarelab timing-test` session (offscreen) gives the timing figures.
// `chromium --headless --dump-dom` prints the page after its script ran; the problems are read
// back from it. The report itself forbids scripts (Content-Security-Policy); the page here is the
// test's own.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>

#include "analysis/analysis_report.h"
#include "analysis/report_output.h"
#include "runner/cli/analysis_words.h"
#include "runner/cli/quest_plus_posteriors.h"
#include "runner/cli/straylight_measurements.h"
#include "tests/cli_process.h"
#include "tests/example_dry_run.h"
#include "tests/headless_chromium.h"
#include "tests/scratch_dir.h"

namespace glarelab::analysis {
namespace {

// The page after its script ran (`--dump-dom`), and chromium's exit status; its log in `dir`.
struct DumpedPage {
  int status = 0;
  std::string dom;
};

DumpedPage dump_dom(const std::string& chromium, const std::string& page_path, const test::ScratchDir& dir) {
  const std::string dom = dir.file("dom.html");
  const std::string command =
      test::headless_chromium_command(chromium, 60, dir.file("profile"), "--window-size=1400,1000 --dump-dom", page_path) +
      " >" + dom + " 2>" + dir.file("chromium.log");
  const int status = std::system(command.c_str());
  return {status, test::read_bytes(dom)};
}

constexpr const char* kCheckScript = R"js(
function boxesOverlap(a, b, tolerance) {
  return a.left < b.right - tolerance && b.left < a.right - tolerance &&
         a.top < b.bottom - tolerance && b.top < a.bottom - tolerance;
}
const problems = [];
let figures = 0, texts = 0;
for (const holder of document.querySelectorAll('div.figure')) {
  const name = holder.dataset.name;
  const svg = holder.querySelector('svg');
  if (!svg) { problems.push(name + ': no svg'); continue; }
  ++figures;
  const view = svg.getBoundingClientRect();
  const boxes = [];
  for (const text of svg.querySelectorAll('text')) {
    const r = text.getBoundingClientRect();
    if (r.width === 0 && r.height === 0) continue;
    ++texts;
    const label = JSON.stringify(text.textContent.slice(0, 40));
    if (r.left < view.left - 0.5 || r.right > view.right + 0.5 || r.top < view.top - 0.5 || r.bottom > view.bottom + 0.5)
      problems.push(name + ': text ' + label + ' leaves the viewport');
    boxes.push([r, label]);
  }
  for (let i = 0; i < boxes.length; ++i)
    for (let j = i + 1; j < boxes.length; ++j)
      if (boxesOverlap(boxes[i][0], boxes[j][0], 0.5))
        problems.push(name + ': texts ' + boxes[i][1] + ' and ' + boxes[j][1] + ' overlap');
  const legend = svg.querySelector('g.legend');
  if (legend) {
    const l = legend.getBoundingClientRect();
    const area = svg.querySelector('rect.plot-area');
    if (area && boxesOverlap(l, area.getBoundingClientRect(), 0.5)) problems.push(name + ': legend overlaps the plotting area');
    for (const mark of svg.querySelectorAll('g.data circle, g.data rect'))
      if (boxesOverlap(l, mark.getBoundingClientRect(), 0.5)) { problems.push(name + ': legend overlaps a data mark'); break; }
  }
  const area = svg.querySelector('rect.plot-area');
  if (area) {
    const a = area.getBoundingClientRect();
    for (const path of svg.querySelectorAll('g.data path')) {
      const r = path.getBoundingClientRect();
      if (r.left < a.left - 1 || r.right > a.right + 1 || r.top < a.top - 1 || r.bottom > a.bottom + 1)
        problems.push(name + ': an interval leaves the plotting area');
    }
  }
  if (/graded_choice|psychometric_/.test(name)) {
    const rings = Array.from(svg.querySelectorAll('g.data circle[fill="white"]'), c =>
        [c.cx.baseVal.value, c.cy.baseVal.value, c.r.baseVal.value]);
    for (let i = 0; i < rings.length; ++i)
      for (let j = i + 1; j < rings.length; ++j)
        if (Math.hypot(rings[i][0] - rings[j][0], rings[i][1] - rings[j][1]) < rings[i][2] + rings[j][2] - 0.05)
          problems.push(name + ': two data rings overlap');
  }
}
document.getElementById('result').textContent =
    'FIGURES ' + figures + ' TEXTS ' + texts + '\n' + problems.map(p => 'PROBLEM ' + p).join('\n') + '\nEND';
)js";

TEST(AnalysisLayout, EveryFigureOfEveryExampleReportLaysOutCleanly) {
  const std::string chromium = test::chromium_binary();
  if (chromium.empty()) GTEST_SKIP() << "chromium is not installed (Debian package chromium; scripts/setup.sh installs it)";
  const test::ScratchDir dir;
  const std::filesystem::path examples = std::filesystem::path(GLARELAB_SOURCE_DIR) / "examples";
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(examples))
    if (entry.path().extension() == ".toml") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 7u);

  std::string page = "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><style>body{margin:0}"
                     "div.figure{margin:8px}</style></head><body>\n";
  std::size_t expected_figures = 0;
  for (const auto& file : files) {
    const std::string stem = file.stem().string();
    const std::string db = dir.file(stem + ".db");
    test::dry_run_example(file.string(), db, {1, 2});
    AnalysisOptions options;
    options.bootstrap_samples = 20;
    options.threads = 2;
    LoadedData data = load_databases({db});
    options.words = cli::figure_words_of(data);  // the [analysis] words, as `analyze` reads them
    AnalysisReport report = analyse(std::move(data), options);
    // The QUEST+ / Psi marginal posteriors, as `glarelab analyze` adds them (runner/cli/command_analyze.cpp).
    add_quest_plus_posteriors(report, rebuild_quest_plus_posteriors(report.data, report.data.notes));
    add_straylight_measurements(report, rebuild_straylight_measurements(report.data, report.data.notes));
    write_report(report, dir.file(stem));
    for (const Figure& figure : report.figures) {
      page += "<div class=\"figure\" data-name=\"" + stem + "/" + figure.file_stem + "\">" + figure.svg + "</div>\n";
      ++expected_figures;
    }
    std::printf("%s: %zu figures\n", stem.c_str(), report.figures.size());
  }
  // A timing test's report: its flip-interval histogram and time series.
  const std::string timing_db = dir.file("timing_test.db");
  const test::RunOutput timing_run =
      test::run_glarelab({"timing-test", "--display", "offscreen", "--frames", "240", "--db", timing_db}, dir.path());
  ASSERT_EQ(timing_run.exit_code, 0) << timing_run.output;
  const AnalysisReport timing_report = analyse(load_databases({timing_db}), AnalysisOptions{});
  write_report(timing_report, dir.file("timing_test"));
  std::size_t timing_figures = 0;
  for (const Figure& figure : timing_report.figures) {
    page += "<div class=\"figure\" data-name=\"timing_test/" + figure.file_stem + "\">" + figure.svg + "</div>\n";
    ++expected_figures;
    timing_figures += figure.file_stem.rfind("flip_", 0) == 0 ? 1 : 0;
  }
  EXPECT_EQ(timing_figures, 2u);
  page += "<pre id=\"result\">script did not run</pre><script>" + std::string(kCheckScript) + "</script></body></html>\n";
  const std::string page_path = dir.file("figures.html");
  std::ofstream(page_path) << page;
  // GLARELAB_LAYOUT_KEEP=DIR keeps the page of figures and every example's report for a look.
  if (const char* keep = std::getenv("GLARELAB_LAYOUT_KEEP"); keep != nullptr && *keep != '\0') {
    std::filesystem::copy_file(page_path, std::filesystem::path(keep) / "figures.html",
                               std::filesystem::copy_options::overwrite_existing);
    for (const auto& file : files)
      std::filesystem::copy(dir.file(file.stem().string()), std::filesystem::path(keep) / file.stem(),
                            std::filesystem::copy_options::recursive | std::filesystem::copy_options::overwrite_existing);
    std::filesystem::copy(dir.file("timing_test"), std::filesystem::path(keep) / "timing_test",
                          std::filesystem::copy_options::recursive | std::filesystem::copy_options::overwrite_existing);
  }

  const auto [status, text] = dump_dom(chromium, page_path, dir);
  std::smatch counts;
  ASSERT_TRUE(std::regex_search(text, counts, std::regex("FIGURES ([0-9]+) TEXTS ([0-9]+)")))
      << "chromium exit status " << status << ": " << test::read_bytes(dir.file("chromium.log")) << text.substr(0, 500);
  EXPECT_EQ(std::stoul(counts[1]), expected_figures);
  EXPECT_GT(std::stoul(counts[2]), 10 * expected_figures);  // titles, ticks, labels: the texts were measured
  std::printf("%s figures, %s text elements measured\n", counts[1].str().c_str(), counts[2].str().c_str());
  // The problems as the script wrote them into the page: from its counts to its END line (the
  // script's own source, dumped after the page's text, is not read).
  const auto from = static_cast<std::size_t>(counts.position(0));
  const std::string written = text.substr(from, text.find("\nEND", from) - from);
  const std::regex problem("PROBLEM ([^\n]*)");
  int problems = 0;
  for (auto it = std::sregex_iterator(written.begin(), written.end(), problem); it != std::sregex_iterator(); ++it) {
    ADD_FAILURE() << (*it)[1].str();
    ++problems;
  }
  EXPECT_EQ(problems, 0);
}

// The report's own page stays within the body's 1150 px when a database lies under a directory
// whose one name is 200 characters long (no '/' to break after): the sessions table's cells wrap
// anywhere rather than widen the page. The report forbids scripts, so its policy line is taken out
// of a copy and a measuring script appended to it.
TEST(AnalysisLayout, ALongSingleWordDirectoryDoesNotWidenTheReportPastThePage) {
  const std::string chromium = test::chromium_binary();
  if (chromium.empty()) GTEST_SKIP() << "chromium is not installed (Debian package chromium; scripts/setup.sh installs it)";
  const test::ScratchDir dir;
  const std::filesystem::path long_dir = std::filesystem::path(dir.path()) / std::string(200, 'd');
  std::filesystem::create_directories(long_dir);
  const std::string db = (long_dir / "demo.db").string();
  test::dry_run_example(std::string(GLARELAB_SOURCE_DIR) + "/examples/ritschel_adjustment.toml", db, {1});
  AnalysisOptions options;
  options.bootstrap_samples = 0;
  const AnalysisReport report = analyse(load_databases({db}), options);
  std::string html = render_html(report);
  const auto policy = html.find("<meta http-equiv=\"Content-Security-Policy\"");
  ASSERT_NE(policy, std::string::npos);
  html.erase(policy, html.find('>', policy) + 1 - policy);
  ASSERT_NE(html.find(std::string(200, 'd')), std::string::npos) << "the path is not in the sessions table";
  const auto body_end = html.rfind("</body>");
  ASSERT_NE(body_end, std::string::npos);
  html.insert(body_end, "<pre id=\"result\">script did not run</pre><script>document.getElementById('result').textContent="
                        "'WIDTH '+Math.ceil(Math.max(...Array.from(document.querySelectorAll('table'),"
                        "t=>t.getBoundingClientRect().right)))+' END';</script>");
  const std::string page_path = dir.file("report.html");
  std::ofstream(page_path) << html;
  const auto [status, text] = dump_dom(chromium, page_path, dir);
  std::smatch width;
  ASSERT_TRUE(std::regex_search(text, width, std::regex("WIDTH ([0-9]+) END")))
      << "chromium exit status " << status << ": " << test::read_bytes(dir.file("chromium.log"));
  // The rightmost table edge: the body is at most 1150 px wide after a 24 px margin.
  EXPECT_LE(std::stoi(width[1]), 24 + 1150 + 1) << "a table runs past the body";
}

}  // namespace
}  // namespace glarelab::analysis

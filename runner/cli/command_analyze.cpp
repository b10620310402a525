#include <sys/stat.h>

#include <filesystem>
#include <iostream>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "analysis/analysis_report.h"
#include "analysis/report_output.h"
#include "analysis/session_selection.h"
#include "analysis/tidy_csv.h"
#include "core/atomic_file.h"
#include "runner/cli/analysis_words.h"
#include "runner/cli/commands.h"
#include "runner/cli/option_checks.h"
#include "runner/cli/quest_plus_posteriors.h"
#include "runner/cli/straylight_measurements.h"

namespace glarelab::cli {
namespace {

// The databases once each: a file named twice (results/*.db results/a.db, or by two paths to the
// same file) would count its sessions twice in every statistic.
std::vector<std::string> distinct_files(const std::vector<std::string>& paths) {
  std::vector<std::string> distinct;
  std::set<std::filesystem::path> seen;
  for (const std::string& path : paths) {
    std::error_code error;
    std::filesystem::path identity = std::filesystem::canonical(path, error);
    if (error) identity = std::filesystem::absolute(path).lexically_normal();
    if (!seen.insert(identity).second) {
      std::cerr << "analyze: " << path << " was given more than once; it is read once\n";
      continue;
    }
    distinct.push_back(path);
  }
  return distinct;
}

// The permission bits of the (first) database: its exports hold the same data, so a database kept
// 0600 does not give 0644 (or, under umask 000, 0666) CSV files beside it.
std::optional<unsigned> export_mode(const std::string& database) {
  struct stat status {};
  if (::stat(database.c_str(), &status) != 0) return std::nullopt;
  return static_cast<unsigned>(status.st_mode) & 0666u;
}

}  // namespace

Action add_analyze_command(CLI::App& app) {
  struct Options {
    std::vector<std::string> databases;
    std::string out = "analysis";
    bool raw_csv_cells = false;
    analysis::SessionSelection selection;
    analysis::AnalysisOptions analysis;
  };
  auto options = std::make_shared<Options>();
  CLI::App* analyze = app.add_subcommand(
      "analyze", "Statistics, fits, tidy CSV and an HTML report (with SVG figures) from one or more results databases");
  analyze->add_option("databases", options->databases, "Results database(s) (SQLite)")->required()->check(CLI::ExistingFile);
  analyze->add_option("--out", options->out, "Output directory (created)")
      ->check(CLI::Validator(
          [](std::string& path) -> std::string {
            // A file where the folder or a folder above it must be (--out results.db/sub) is the
            // user's mistake (exit 2), not the storage failing.
            const std::optional<std::string> file = file_in_the_way_of_folder(path);
            if (!file) return {};
            return *file == path ? path + " is a file, not a directory" : path + ": " + *file + " is a file, not a directory";
          },
          "DIR"))
      ->capture_default_str();
  analyze->add_flag("--raw-csv-cells", options->raw_csv_cells,
                    "Write CSV cells as stored, even those a spreadsheet would run as a formula (= + - @); by default "
                    "such cells get a leading apostrophe");
  analyze->add_option("--session", options->selection.session_ids,
                      "Analyse only the session(s) with this id (repeatable; with --participant, both must match)")
      ->allow_extra_args(false);
  analyze->add_option("--participant", options->selection.participants,
                      "Analyse only the sessions of this participant (repeatable)")
      ->allow_extra_args(false);
  analyze->add_option("--bootstrap", options->analysis.bootstrap_samples,
                      "Parametric bootstrap samples per psychometric fit (0: no intervals)")
      ->capture_default_str()
      ->check(CLI::Range(0, 100000));
  analyze->add_option("--reversals", options->analysis.last_reversals,
                      "Staircase threshold: mean of the last K reversals")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  analyze->add_option("--threads", options->analysis.threads,
                      "Threads for the psychometric fits (0: one per hardware thread; results do not depend on it)")
      ->capture_default_str()
      ->check(CLI::Range(0u, 1024u));
  analyze->add_option("--seed", options->analysis.seed, "Seed of the bootstrap draws")
      ->check(seed_check())
      ->capture_default_str();
  return [=]() {
    return report_errors([&]() {
      analysis::keep_formula_cells_raw(options->raw_csv_cells);
      analysis::LoadedData data = analysis::load_databases(distinct_files(options->databases));
      analysis::select_sessions(data, options->selection);
      analysis::AnalysisOptions analysis_options = options->analysis;
      analysis_options.words = figure_words_of(data);
      analysis::AnalysisReport report = analysis::analyse(std::move(data), analysis_options);
      // QUEST+ / Psi posteriors need the procedure (protocols/), which analysis/ may not build.
      analysis::add_quest_plus_posteriors(report, rebuild_quest_plus_posteriors(report.data, report.data.notes));
      analysis::add_straylight_measurements(report, rebuild_straylight_measurements(report.data, report.data.notes));
      const auto written = analysis::write_report(report, options->out, export_mode(options->databases.front()));
      std::cout << analysis::render_terminal_summary(report);
      std::cout << "  wrote " << written.size() << " files to " << options->out << " (report.html, trials.csv, figures/)\n";
      return 0;
    });
  };
}

}  // namespace glarelab::cli

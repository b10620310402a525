#pragma once
// Rendering an analysis: the self-contained HTML report (inline SVG, no scripts, no network;
// every text from the database HTML-escaped), the short terminal summary, and writing
// everything (CSV, report.html, figures/*.svg) into the output directory.
#include <optional>
#include <string>
#include <vector>

#include "analysis/analysis_report.h"

namespace glarelab::analysis {

std::string render_html(const AnalysisReport& report);
std::string render_terminal_summary(const AnalysisReport& report);

// Writes the tidy CSV files, report.html and figures/<stem>.svg into `directory` (created), each
// beside its name and renamed into place (core/atomic_file.h), with the permission bits `mode`
// when given; then manifest.txt, the list of them, and removes what the previous manifest listed
// and this analysis did not write. Returns the paths written (the manifest not among them).
std::vector<std::string> write_report(const AnalysisReport& report, const std::string& directory,
                                      std::optional<unsigned> mode = std::nullopt);

}  // namespace glarelab::analysis

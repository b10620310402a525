#pragma once
// Rendering an analysis: the self-contained HTML report (inline SVG, no scripts, no network;
// every text from the database HTML-escaped), the short terminal summary, and writing
// everything (CSV, report.html, figures/*.svg) into the output directory.
#include <string>
#include <vector>

#include "analysis/analysis_report.h"

namespace glarelab::analysis {

std::string render_html(const AnalysisReport& report);
std::string render_terminal_summary(const AnalysisReport& report);

// Writes the tidy CSV files, report.html and figures/<stem>.svg into `directory` (created);
// returns the paths written.
std::vector<std::string> write_report(const AnalysisReport& report, const std::string& directory);

}  // namespace glarelab::analysis

#include "analysis/analysis_report.h"

namespace glarelab::analysis {

AnalysisReport analyse(LoadedData data, const AnalysisOptions& options) {
  AnalysisReport report;
  report.data = std::move(data);
  report.options = options;
  report.forced_choice = analyse_forced_choice(report.data);
  StaircaseOptions staircase_options;
  staircase_options.bootstrap_samples = options.bootstrap_samples;
  staircase_options.last_reversals = options.last_reversals;
  staircase_options.seed = options.seed;
  staircase_options.threads = options.threads;
  report.staircases = analyse_staircases(report.data, staircase_options);
  PseOptions pse_options;
  pse_options.last_reversals = options.last_reversals;
  pse_options.bootstrap_samples = options.bootstrap_samples;
  pse_options.seed = options.seed;
  pse_options.threads = options.threads;
  report.pse = analyse_pse(report.data, pse_options);
  report.adjustments = analyse_adjustments(report.data);
  report.ratings = analyse_ratings(report.data);
  report.timing = analyse_timing(report.data);
  report.tracker = analyse_tracker(report.data);
  report.figures = draw_figures(report);
  return report;
}

}  // namespace glarelab::analysis

#include "analysis/analysis_report.h"

namespace glarelab::analysis {

AnalysisReport analyse(LoadedData data, const AnalysisOptions& options) {
  AnalysisReport report;
  report.data = std::move(data);
  report.options = options;
  GradedChoiceOptions graded_options;
  graded_options.bootstrap_samples = options.bootstrap_samples;
  graded_options.seed = options.seed;
  graded_options.threads = options.threads;
  report.graded_choice = analyse_graded_choice(report.data, graded_options);
  report.forced_choice = analyse_forced_choice(
      report.data, [&](const LoadedTrial& trial) { return is_graded_trial(trial, report.graded_choice); });
  report.paired_scales = scale_pooled_pairs(report.forced_choice);
  StaircaseOptions staircase_options;
  staircase_options.bootstrap_samples = options.bootstrap_samples;
  staircase_options.last_reversals = options.last_reversals;
  staircase_options.seed = options.seed;
  staircase_options.threads = options.threads;
  report.staircases = analyse_staircases(report.data, staircase_options);
  PseOptions pse_options;
  pse_options.last_reversals = options.last_reversals;
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

#pragma once
// The final posterior of each QUEST+ / Psi track (Watson 2017; Kontsevich & Tyler 1999) as plain
// data for the report: per parameter its grid, marginal posterior and the summary the procedure
// logs (value at the joint mode, marginal mean and SD). The posterior itself is rebuilt by the
// runner, which replays a session's stored trials through the procedure as resume does
// (runner/cli/quest_plus_posteriors.h); this file only reports and draws it.
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "analysis/figure_words.h"

namespace glarelab::analysis {

struct MarginalPosterior {
  std::string parameter;               // "threshold", "slope", "lapse", ...
  std::string unit;                    // of the grid values, e.g. "dB cd/m2"; "" for a probability or a pure number
  std::vector<double> values;          // the parameter's grid
  std::vector<double> probabilities;   // marginal posterior at each grid value (sums to 1)
  double mode = 0.0;  // the parameter's value at the joint posterior maximum
  double mean = 0.0;  // marginal posterior mean
  double sd = 0.0;    // marginal posterior SD
};

struct QuestPlusPosterior {
  std::string participant_label;  // LoadedSession::label
  std::string track;              // the track's name in the experiment
  std::string method;             // quest_plus | psi
  int trials = 0;                 // answered trials the posterior includes
  std::vector<MarginalPosterior> marginals;  // in the procedure's parameter order
};

// The axis label of a parameter: its name and, when it has one, its unit in parentheses.
std::string parameter_axis_label(const MarginalPosterior& marginal);

// The central 95 % of a marginal on its grid: the first grid values at which the cumulative
// posterior reaches 0.025 and 0.975.
std::pair<double, double> marginal_credible_interval(const MarginalPosterior& marginal);

// Empty, or a warning when the value at the joint mode or the marginal mean lies within half a
// grid step of the grid's first or last value: the posterior is cut off there, so the estimate
// may lie beyond the grid and its interval is too narrow (the grid should be widened). Not for
// probabilities (guess, lapse), whose grids end at their natural bounds.
std::string grid_edge_warning(const MarginalPosterior& marginal);

// One figure per parameter of a track: the marginal posterior over the parameter's grid (line
// and markers at the grid points), the marginal mean as a dashed vertical line, and the mode,
// mean and SD in the note under the title.
// `words`: the track's display name ([analysis.names]); the method is named as its paper does.
std::string marginal_posterior_svg(const QuestPlusPosterior& track, std::size_t parameter, const FigureWords& words = {});

// The report's table (one row per track and parameter) and the terminal lines.
std::string quest_plus_posteriors_html(const std::vector<QuestPlusPosterior>& tracks);
std::string quest_plus_posteriors_terminal(const std::vector<QuestPlusPosterior>& tracks);
// Tidy CSV (RFC 4180 as analysis/tidy_csv.h, CRLF, numbers that read back exactly): participant,
// track, method, trials, parameter, unit, value, probability (one row per grid point).
std::string quest_plus_posteriors_csv(const std::vector<QuestPlusPosterior>& tracks);

}  // namespace glarelab::analysis

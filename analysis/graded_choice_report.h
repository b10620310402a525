#pragma once
// The graded forced-choice analysis (analysis/graded_choice_analysis.h) in the report: the HTML
// section's table and sentences, the terminal lines, and the figure of the proportions with the
// fitted curves and PSEs.
#include <string>

#include "analysis/analysis_report.h"
#include "analysis/figure_words.h"

namespace glarelab::analysis {

// The section's heading, explanation, table and test sentence (figures are added by the caller).
std::string graded_choice_html(const GradedChoiceAnalysis& analysis, int bootstrap_samples);

// One "graded choice ..." line per group and one for the test.
std::string graded_choice_terminal(const GradedChoiceAnalysis& analysis);

// Proportion naming scene_b against the graded variable per group: points sized by their number
// of answers, the fitted curves (psignifit 4's fits of the pooled answers,
// GradedChoiceGroup::psignifit), and each PSE at 1/2 with its 95 % credible interval.
Figure graded_choice_figure(const GradedChoiceAnalysis& analysis, const FigureWords& words);
// The graded variable's axis words (FigureWords, else the column's name), with its unit and scale.
std::string graded_axis_label(const GradedChoiceAnalysis& analysis, const FigureWords& words);

// "0.0414 (ratio 1.1)" on a log10 axis, else the value.
std::string graded_value_text(const GradedChoiceAnalysis& analysis, double x);

}  // namespace glarelab::analysis

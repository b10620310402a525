#include "analysis/graded_choice_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <sstream>

#include "analysis/report_numbers.h"
#include "analysis/statistics.h"
#include "analysis/figure_words.h"
#include "analysis/svg_plot.h"
#include "analysis/within_participant_report.h"

namespace glarelab::analysis {
namespace {

std::string interval_text(const std::optional<Interval>& interval, const std::function<std::string(double)>& value) {
  if (!interval) return "-";
  return value(interval->low) + " to " + value(interval->high);
}

std::optional<Interval> pse_interval(const GradedChoiceGroup& group) {
  if (!group.posterior) return std::nullopt;
  return group.posterior->credible;
}

long answers(const GradedChoiceGroup& group) {
  long n = 0;
  for (const StimulusLevel& level : group.levels) n += level.trials;
  return n;
}

std::string test_sentence(const GradedChoiceAnalysis& analysis) {
  const SharedPseTest& test = analysis.shared_pse;
  if (!test.ok()) return "One PSE for every group against one per group: not computed (" + test.unavailable + ").";
  return "One PSE for every group against one per group (each with its own slope): likelihood ratio G = " +
         general(test.statistic) + ", chi2(" + std::to_string(test.df) + "), " + format_p(test.p_value) +
         "; shared PSE " + graded_value_text(analysis, test.shared_pse) + ".";
}

std::string cell(const std::string& text) { return "<td>" + html_escape(text) + "</td>"; }

}  // namespace

std::string graded_value_text(const GradedChoiceAnalysis& analysis, double x) {
  if (!analysis.log10_axis) return general(x);
  return general(x) + " (ratio " + general(std::pow(10.0, x)) + ")";
}

std::string graded_choice_html(const GradedChoiceAnalysis& analysis, int bootstrap_samples) {
  std::ostringstream out;
  out << "<h2>Forced choice with a graded variable</h2>\n<p>Proportion of answers naming scene_b against "
      << html_escape(analysis.axis_label())
      << " per glare group; a maximum-likelihood cumulative normal without guess or lapse rate per group. The point of "
         "subjective equality (PSE) is where it crosses 1/2; its 95% interval is the central 95% of its posterior (a grid "
         "over PSE and width with weak priors from the tested levels, after Schuett et al. 2016), which keeps its "
         "coverage with few answers per group where bootstrap percentiles do not. The shift is each group's PSE minus "
         "that of the baseline ('"
      << html_escape(analysis.baseline)
      << "'), its interval the central 95% of the difference of the two posteriors; the slope's interval is the "
         "parametric bootstrap's ("
      << bootstrap_samples
      << " samples). Where answers separate perfectly there is no maximum-likelihood fit and the PSE shown is the "
         "posterior median. Answers naming no side are left out of the fit.</p>\n";
  if (analysis.within.participants.size() > 1)
    out << "<p>This table pools the answers of " << html_escape(participants_sentence(analysis))
        << " into one fit per group; the per-participant analysis follows it.</p>\n";
  out << "<table><tr><th>group</th><th>answers</th><th>neither</th><th>PSE</th><th>95% interval</th><th>slope</th>"
         "<th>95% interval</th><th>shift from " << html_escape(analysis.baseline) << "</th><th>95% interval</th></tr>\n";
  for (const GradedChoiceGroup& g : analysis.groups) {
    out << "<tr>" << cell(g.name) << cell(std::to_string(answers(g))) << cell(std::to_string(g.neither));
    const auto value = [&](double x) { return graded_value_text(analysis, x); };
    if (g.fit.ok()) {
      out << cell(value(g.fit.threshold)) << cell(interval_text(pse_interval(g), value)) << cell(general(g.fit.slope))
          << cell(g.fit.slope_ci ? general(g.fit.slope_ci->low) + " to " + general(g.fit.slope_ci->high) : "-");
    } else if (g.posterior) {
      out << cell(value(g.posterior->median) + " (posterior median)") << cell(interval_text(pse_interval(g), value))
          << "<td colspan=\"2\">" << html_escape("no ML fit: " + g.fit.unavailable) << "</td>";
    } else {
      out << "<td colspan=\"4\">" << html_escape("no fit: " + g.fit.unavailable) << "</td>";
    }
    out << cell(g.shift ? general(*g.shift) : "-")
        << cell(interval_text(g.shift_interval, general))
        << "</tr>\n";
  }
  out << "</table>\n";
  if (analysis.groups.size() >= 2) out << "<p>" << html_escape(test_sentence(analysis)) << "</p>\n";
  out << within_participant_html(analysis);
  if (!analysis.notes.empty()) {
    out << "<ul>\n";
    for (const std::string& note : analysis.notes) out << "<li>" << html_escape(note) << "</li>\n";
    out << "</ul>\n";
  }
  return out.str();
}

std::string graded_choice_terminal(const GradedChoiceAnalysis& analysis) {
  std::string text;
  for (const GradedChoiceGroup& g : analysis.groups) {
    text += "  graded choice " + g.name + " (" + analysis.axis_label() + "): ";
    if (!g.pse()) {
      text += "no fit (" + g.fit.unavailable + ")\n";
      continue;
    }
    text += "PSE " + graded_value_text(analysis, *g.pse());
    if (!g.fit.ok()) text += " (posterior median; no ML fit: " + g.fit.unavailable + ")";
    if (g.posterior) text += " [" + interval_text(pse_interval(g), general) + "]";
    if (g.shift) {
      text += "; shift from " + analysis.baseline + " " + general(*g.shift);
      if (g.shift_interval) text += " [" + interval_text(g.shift_interval, general) + "]";
    }
    text += "\n";
  }
  if (analysis.groups.size() >= 2) text += "  graded choice test: " + test_sentence(analysis) + "\n";
  return text + within_participant_terminal(analysis);
}

std::string graded_axis_label(const GradedChoiceAnalysis& analysis, const FigureWords& words) {
  std::string label = words.graded_label.empty() ? column_words(analysis.variable) : words.graded_label;
  if (!words.graded_unit.empty()) label += " (" + words.graded_unit + ")";
  return analysis.log10_axis ? label + ", log10 scale" : label;
}

// Spencer et al. 1995, Figs. 12-13, asked with two sides: per glare group the proportions, the
// psignifit 4 fit of the pooled answers (its MAP curve, the same fit the per-participant PSEs
// use: analysis/psignifit_pse.h) and its PSE with the threshold's 95 % credible interval.
Figure graded_choice_figure(const GradedChoiceAnalysis& analysis, const FigureWords& words) {
  const std::string answer = words.answer_label.empty() ? "proportion choosing scene_b" : words.answer_label;
  SvgPlot plot("Psychometric functions per " + (words.group_label.empty() ? std::string("glare") : words.group_label) +
                   ": " + answer + " (psignifit 4, 95% credible intervals)",
               graded_axis_label(analysis, words), answer, 640, 360);
  double low = std::numeric_limits<double>::infinity();
  double high = -low;
  for (const GradedChoiceGroup& g : analysis.groups) {
    for (const StimulusLevel& level : g.levels) {
      low = std::min(low, level.intensity);
      high = std::max(high, level.intensity);
    }
  }
  if (!(high >= low)) {
    low = 0.0;
    high = 1.0;
    plot.note("no answers naming a side");
  }
  const double pad = 0.06 * std::max(high - low, 1e-9);
  plot.set_x_range(low - pad, high + pad);
  plot.set_y_range(0.0, 1.0);
  plot.horizontal_rule(0.5, "#888");
  std::vector<std::vector<CountedPoint>> rings;
  std::vector<std::string> colours;
  for (std::size_t g = 0; g < analysis.groups.size(); ++g) {
    rings.emplace_back();
    colours.push_back(series_colour(g));
    for (const StimulusLevel& level : analysis.groups[g].levels)
      rings.back().push_back({level.intensity, static_cast<double>(level.correct) / static_cast<double>(std::max(level.trials, 1L)),
                              level.trials});
  }
  counted_rings(plot, rings, colours);
  for (std::size_t g = 0; g < analysis.groups.size(); ++g) {
    const GradedChoiceGroup& group = analysis.groups[g];
    const std::string& colour = series_colour(g);
    const std::string name = words.display(group.name);
    if (!group.psignifit) {
      plot.note(name + ": no fit (fewer than two levels answered)");
      plot.legend(name + " (no fit)", colour);
      continue;
    }
    const PsignifitPse& fit = *group.psignifit;
    std::vector<double> x, y;
    for (int i = 0; i <= 120; ++i) {
      x.push_back(low - pad + (high - low + 2.0 * pad) * i / 120.0);
      y.push_back(fit.probability(x.back()));
    }
    plot.line(x, y, colour, 2.0);
    // The intervals stacked below the 1/2 line, one row per group, so they never hide each other;
    // an end beyond the plot becomes an arrowhead at its edge (SvgPlot::horizontal_error_bar).
    plot.horizontal_error_bar(0.5 - 0.045 * static_cast<double>(g + 1), fit.credible.low, fit.credible.high, colour);
    plot.markers({fit.pse}, {fit.probability(fit.pse)}, colour, 4.5);
    plot.legend(name + ": PSE " + graded_value_text(analysis, fit.pse), colour);
  }
  return {"graded_choice", "graded_choice",
          "Proportion of answers (" + answer + ") against " + graded_axis_label(analysis, words) +
              " per group (rings: the data, area by number of answers, groups side by side), psignifit 4's fit of the "
              "pooled answers per group (MAP curve: cumulative normal, guess and lapse 0, overdispersion free; Schuett "
              "et al. 2016), and each PSE (dot at 1/2) with its 95% credible interval (bars below, in the legend's order).",
          plot.svg()};
}

}  // namespace glarelab::analysis

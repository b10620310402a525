#include "analysis/quest_plus_posterior.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "analysis/analysis_report.h"
#include "analysis/report_numbers.h"
#include "analysis/svg_plot.h"
#include "analysis/tidy_csv.h"

namespace glarelab::analysis {
namespace {

std::string cell(const std::string& text) { return "<td>" + html_escape(text) + "</td>"; }

}  // namespace

std::pair<double, double> marginal_credible_interval(const MarginalPosterior& m) {
  double total = 0.0;
  for (double p : m.probabilities) total += p;
  const auto at = [&](double fraction) {
    double cumulative = 0.0;
    for (std::size_t i = 0; i < m.values.size(); ++i) {
      cumulative += m.probabilities[i];
      if (cumulative >= fraction * total) return m.values[i];
    }
    return m.values.back();
  };
  return {at(0.025), at(0.975)};
}

std::string grid_edge_warning(const MarginalPosterior& m) {
  // A probability's grid ends at its natural bounds (a lapse rate of 0 is an estimate, not a cut-off).
  if (m.values.size() < 3 || m.unit == "probability") return {};
  const double low = *std::min_element(m.values.begin(), m.values.end());
  const double high = *std::max_element(m.values.begin(), m.values.end());
  const double half_step = 0.5 * (high - low) / static_cast<double>(m.values.size() - 1);
  const std::string unit = m.unit.empty() || m.unit == "no unit" ? "" : " " + m.unit;
  for (const auto& [what, value] : {std::pair<std::string, double>{"mode", m.mode}, {"mean", m.mean}}) {
    if (value <= low + half_step)
      return "the " + m.parameter + " " + what + " (" + general(value) + unit + ") sits at the grid's lowest value (" +
             general(low) + unit + "): the estimate may lie below the grid; widen it";
    if (value >= high - half_step)
      return "the " + m.parameter + " " + what + " (" + general(value) + unit + ") sits at the grid's highest value (" +
             general(high) + unit + "): the estimate may lie above the grid; widen it";
  }
  return {};
}

std::string parameter_axis_label(const MarginalPosterior& marginal) {
  return marginal.parameter + (marginal.unit.empty() ? "" : " (" + marginal.unit + ")");
}

namespace {

// The method as its paper names it (Watson 2017's QUEST+, Kontsevich and Tyler 1999's Psi).
std::string method_words(const std::string& method) {
  if (method == "quest_plus") return "QUEST+";
  if (method == "psi") return "Psi";
  return method;
}

}  // namespace

std::string marginal_posterior_svg(const QuestPlusPosterior& track, std::size_t parameter, const FigureWords& words) {
  const MarginalPosterior& m = track.marginals.at(parameter);
  SvgPlot plot(method_words(track.method) + " posterior of " + m.parameter + ": " + words.display(track.track) + ", " +
                   track.participant_label +
                   " (" + std::to_string(track.trials) + " trials)",
               parameter_axis_label(m), "marginal posterior probability");
  const double low = *std::min_element(m.values.begin(), m.values.end());
  const double high = *std::max_element(m.values.begin(), m.values.end());
  const double peak = *std::max_element(m.probabilities.begin(), m.probabilities.end());
  plot.set_x_range(low, high);
  plot.set_y_range(0.0, std::max(peak, 1e-12) * 1.05);
  const std::string& colour = series_colour(0);
  if (m.values.size() > 1) plot.line(m.values, m.probabilities, colour);
  plot.markers(m.values, m.probabilities, colour);
  // The marginal mean as a dashed vertical line: where the summary's mean lies on the curve.
  plot.line({m.mean, m.mean}, {0.0, std::max(peak, 1e-12) * 1.05}, series_colour(1), 1.5, true);
  plot.legend("marginal posterior", colour);
  plot.legend("marginal mean", series_colour(1));
  const auto [ci_low, ci_high] = marginal_credible_interval(m);
  plot.note("mode " + general(m.mode) + ", mean " + general(m.mean) + ", SD " + general(m.sd) + ", 95% " +
            general(ci_low) + " to " + general(ci_high) + (m.unit.empty() ? "" : " (" + m.unit + ")"));
  if (const std::string warning = grid_edge_warning(m); !warning.empty()) plot.note("warning: " + warning);
  return plot.svg();
}

std::string quest_plus_posteriors_html(const std::vector<QuestPlusPosterior>& tracks) {
  std::ostringstream out;
  out << "<table><tr><th>participant</th><th>track</th><th>method</th><th>trials</th><th>parameter</th>"
         "<th>mode</th><th>mean</th><th>SD</th><th>95% interval</th><th>grid</th></tr>\n";
  for (const QuestPlusPosterior& t : tracks) {
    for (const MarginalPosterior& m : t.marginals) {
      const std::string grid = m.values.size() == 1 ? "fixed at " + general(m.values.front())
                                                    : std::to_string(m.values.size()) + " values, " +
                                                          general(m.values.front()) + " .. " + general(m.values.back());
      out << "<tr>" << cell(t.participant_label) << cell(t.track) << cell(t.method) << cell(std::to_string(t.trials))
          << cell(parameter_axis_label(m)) << cell(general(m.mode)) << cell(general(m.mean)) << cell(general(m.sd));
      const auto [ci_low, ci_high] = marginal_credible_interval(m);
      const std::string warning = grid_edge_warning(m);
      out << cell(general(ci_low) + " to " + general(ci_high))
          << (warning.empty() ? cell(grid) : "<td>" + html_escape(grid) + "<br><span class=\"note\">warning: " +
                                                 html_escape(warning) + "</span></td>")
          << "</tr>\n";
    }
  }
  out << "</table>\n";
  return out.str();
}

std::string quest_plus_posteriors_terminal(const std::vector<QuestPlusPosterior>& tracks) {
  std::ostringstream out;
  for (const QuestPlusPosterior& t : tracks) {
    out << "  " << t.method << " " << t.participant_label << " " << t.track << " (" << t.trials << " trials):";
    for (std::size_t i = 0; i < t.marginals.size(); ++i) {
      const MarginalPosterior& m = t.marginals[i];
      const auto [ci_low, ci_high] = marginal_credible_interval(m);
      out << (i == 0 ? " " : "; ") << parameter_axis_label(m) << " mean " << general(m.mean) << ", SD "
          << general(m.sd) << ", mode " << general(m.mode) << ", 95% " << general(ci_low) << " to " << general(ci_high);
      if (const std::string warning = grid_edge_warning(m); !warning.empty()) out << " (warning: " << warning << ")";
    }
    out << "\n";
  }
  return out.str();
}

std::string quest_plus_posteriors_csv(const std::vector<QuestPlusPosterior>& tracks) {
  std::ostringstream out;
  out << "participant,track,method,trials,parameter,unit,value,probability\r\n";
  for (const QuestPlusPosterior& t : tracks)
    for (const MarginalPosterior& m : t.marginals)
      for (std::size_t i = 0; i < m.values.size(); ++i)
        out << csv_field(t.participant_label) << ',' << csv_field(t.track) << ',' << csv_field(t.method) << ','
            << t.trials << ',' << csv_field(m.parameter) << ',' << csv_field(m.unit) << ','
            << csv_number(m.values[i]) << ',' << csv_number(m.probabilities[i]) << "\r\n";
  return out.str();
}

void add_quest_plus_posteriors(AnalysisReport& report, std::vector<QuestPlusPosterior> posteriors) {
  report.quest_plus = std::move(posteriors);
  for (std::size_t t = 0; t < report.quest_plus.size(); ++t) {
    const QuestPlusPosterior& track = report.quest_plus[t];
    for (std::size_t p = 0; p < track.marginals.size(); ++p)
      report.figures.push_back({"quest_plus_" + std::to_string(t + 1) + "_" + std::to_string(p + 1), "quest_plus",
                                "Marginal posterior of " + track.marginals[p].parameter + " after the last trial of " +
                                    report.options.words.display(track.track) + " (" + track.participant_label + ").",
                                marginal_posterior_svg(track, p, report.options.words)});
  }
}

}  // namespace glarelab::analysis

#include "analysis/within_participant_report.h"

#include <cstdio>
#include <sstream>

#include "analysis/graded_choice_report.h"
#include "analysis/report_numbers.h"
#include "analysis/svg_plot.h"

namespace glarelab::analysis {
namespace {

std::string joined(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "" : ", ") + item;
  return text;
}

std::string cell(const std::string& text) { return "<td>" + html_escape(text) + "</td>"; }

std::string interval_text(const Interval& interval) { return general(interval.low) + " to " + general(interval.high); }

std::string effect_sentence(const GradedChoiceAnalysis& analysis, const WithinParticipantEffect& effect) {
  const std::size_t n = effect.participants.size();
  std::string text = effect.group + " - " + analysis.within.baseline + ", within participants (" + std::to_string(n) +
                     " participant" + (n == 1 ? "" : "s") + " with both): ";
  if (n == 0) return text + "no participant has a PSE at both levels.";
  text += "mean shift " + general(effect.mean_shift);
  if (effect.interval) text += ", 95% t interval " + interval_text(*effect.interval);
  if (effect.paired_t.ok()) {
    text += "; paired t(" + general(effect.paired_t.df1) + ") = " + general(effect.paired_t.statistic) + ", " +
            format_p(effect.paired_t.p_value);
  } else {
    text += "; paired t test not run: " + effect.paired_t.unavailable;
  }
  if (effect.wilcoxon.ok()) {
    text += "; Wilcoxon signed-rank T = " + general(effect.wilcoxon.statistic) + ", " +
            (effect.wilcoxon.exact ? "exact " : "normal approximation, ") + format_p(effect.wilcoxon.p_value);
  } else {
    text += "; Wilcoxon signed-rank test not run: " + effect.wilcoxon.unavailable;
  }
  return text + ".";
}

}  // namespace

std::string participants_sentence(const GradedChoiceAnalysis& analysis) {
  const std::size_t n = analysis.within.participants.size();
  return std::to_string(n) + " participant" + (n == 1 ? "" : "s") + " (" + joined(analysis.within.participants) + ") in " +
         std::to_string(analysis.sessions.size()) + " session" + (analysis.sessions.size() == 1 ? "" : "s") + " (" +
         joined(analysis.sessions) + ")";
}

std::string within_participant_html(const GradedChoiceAnalysis& analysis) {
  const WithinParticipantAnalysis& within = analysis.within;
  if (within.empty()) return {};
  std::ostringstream out;
  out << "<h3>Per participant</h3>\n<p>" << html_escape(participants_sentence(analysis))
      << ". Each participant's own psychometric function per group: psignifit 4's posterior (Schuett et al. 2016; "
         "cumulative normal, no guess or lapse rate, overdispersion free), the PSE its MAP threshold with the central 95% "
         "of the threshold's marginal, the shift from '"
      << html_escape(within.baseline) << "' the participant's own with the central 95% of the difference of the two posteriors. ";
  if (within.within) {
    out << "The groups vary within participants, so each effect is the mean of the participants' own shifts with its t "
           "interval and the paired t test (the summary-statistics random-effects analysis, Holmes &amp; Friston 1998), "
           "and the exact signed-rank test from "
        << kWilcoxonMinimumParticipants << " participants.";
  } else {
    out << "Every participant answered one group only: the groups are compared between participants, as independent "
           "groups (the pooled table above).";
  }
  out << "</p>\n<table><tr><th>participant</th><th>group</th><th>answers</th><th>PSE</th><th>95% interval</th><th>shift from "
      << html_escape(within.baseline) << "</th><th>95% interval</th></tr>\n";
  for (const ParticipantCell& c : within.cells) {
    out << "<tr>" << cell(c.participant) << cell(c.group) << cell(std::to_string(c.answers()));
    if (c.fit) out << cell(graded_value_text(analysis, c.fit->pse)) << cell(interval_text(c.fit->credible));
    else out << "<td colspan=\"2\">no fit: fewer than two levels answered</td>";
    out << cell(c.shift ? general(*c.shift) : "-") << cell(c.shift_interval ? interval_text(*c.shift_interval) : "-") << "</tr>\n";
  }
  out << "</table>\n";
  for (const WithinParticipantEffect& effect : within.effects) out << "<p>" << html_escape(effect_sentence(analysis, effect)) << "</p>\n";
  return out.str();
}

std::string within_participant_terminal(const GradedChoiceAnalysis& analysis) {
  const WithinParticipantAnalysis& within = analysis.within;
  if (within.empty()) return {};
  std::string text = "  graded choice participants: " + participants_sentence(analysis) + "\n";
  for (const WithinParticipantEffect& effect : within.effects) text += "  graded choice effect " + effect_sentence(analysis, effect) + "\n";
  return text;
}

}  // namespace glarelab::analysis

#include "analysis/report_output.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "analysis/graded_choice_report.h"
#include "analysis/paired_scale_report.h"
#include "analysis/rating_report.h"
#include "analysis/report_numbers.h"
#include "analysis/session_observer_eye.h"
#include "analysis/svg_plot.h"
#include "analysis/tidy_csv.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/software_version.h"

namespace glarelab::analysis {
namespace {

std::string describe(const TestResult& test, const char* symbol) {
  if (!test.ok()) return "not computed: " + test.unavailable;
  return std::string(symbol) + "(" + general(test.df1) + ") = " + fixed(test.statistic, 2) + ", " + format_p(test.p_value);
}

std::string describe_binomial(const TestResult& test) {
  if (!test.ok()) return "not computed: " + test.unavailable;
  return "exact binomial " + format_p(test.p_value);
}

std::string describe_anova(const RepeatedMeasuresAnova& anova) {
  if (!anova.ok()) return "not computed: " + anova.unavailable;
  std::string text = "F(" + general(anova.df_condition) + ", " + general(anova.df_error) + ") = " + fixed(anova.f, 2) +
                     ", " + format_p(anova.p_value) + " (" + std::to_string(anova.subjects) + " participants)";
  if (anova.levels >= 3) {
    text += "; Greenhouse-Geisser epsilon = " + fixed(anova.epsilon_gg, 3) + ", corrected F(" +
            fixed(anova.df_condition * anova.epsilon_gg, 2) + ", " + fixed(anova.df_error * anova.epsilon_gg, 2) + "), " +
            format_p(anova.p_value_gg);
  }
  return text;
}

std::string preference_sentence(const PairPreference& p) {
  const long decided = p.chose_a + p.chose_b;
  std::string text = p.group + ": '" + p.option_a + "' over '" + p.option_b + "' in " + std::to_string(p.chose_a) + " of " +
                     std::to_string(decided) + " (" + fixed(100.0 * p.share_a(), 1) + "%" +
                     (decided > 0 ? ", 95% CI " + fixed(100.0 * p.share_a_interval.low, 1) + " to " +
                                        fixed(100.0 * p.share_a_interval.high, 1) + "%"
                                  : std::string()) +
                     "); " +
                     describe(p.chi_square, "chi2") + "; " + describe_binomial(p.binomial);
  if (p.neither > 0) text += "; 'neither' " + std::to_string(p.neither) + " (" + fixed(100.0 * p.neither_share(), 1) + "% of all answers)";
  return text;
}

// Percent correct of scored forced-choice trials.
std::string scored_sentence(const ScoredShare& s) {
  return s.group + ": " + std::to_string(s.correct) + " of " + std::to_string(s.trials) + " correct (" + fixed(s.percent(), 1) +
         "%, 95% CI " + fixed(100.0 * s.interval.low, 1) + " to " + fixed(100.0 * s.interval.high, 1) +
         "%); exact binomial test against chance (50%): " + (s.binomial.ok() ? format_p(s.binomial.p_value) : s.binomial.unavailable);
}

std::string fit_sentence(const PsychometricFit& fit) {
  if (!fit.ok()) return shape_name(fit.shape) + ": " + fit.unavailable;
  std::string text = shape_name(fit.shape) + ": threshold " + general(fit.threshold);
  if (fit.threshold_ci) text += " [" + general(fit.threshold_ci->low) + ", " + general(fit.threshold_ci->high) + "]";
  text += ", slope " + general(fit.slope);
  if (fit.slope_ci) text += " [" + general(fit.slope_ci->low) + ", " + general(fit.slope_ci->high) + "]";
  text += ", lapse " + fixed(fit.lapse, 3) + ", deviance " + fixed(fit.deviance, 2) + " (df " +
          std::to_string(fit.deviance_df) + ")";
  if (fit.bootstrap_failures > 0) text += ", " + std::to_string(fit.bootstrap_failures) + " bootstrap refits not identifiable";
  return text;
}

void html_list(std::ostringstream& out, const std::vector<std::string>& items) {
  if (items.empty()) return;
  out << "<ul>\n";
  for (const std::string& item : items) out << "<li>" << html_escape(item) << "</li>\n";
  out << "</ul>\n";
}

void html_figures(std::ostringstream& out, const AnalysisReport& report, const std::string& section) {
  for (const Figure& figure : report.figures) {
    if (figure.section != section) continue;
    out << "<figure id=\"fig-" << html_escape(figure.file_stem) << "\">\n" << figure.svg << "<figcaption>"
        << html_escape(figure.caption) << " (also figures/" << html_escape(figure.file_stem) << ".svg)</figcaption></figure>\n";
  }
}

std::string cell(const std::string& text) { return "<td>" + html_escape(text) + "</td>"; }

// A file path that may break after each '/', so a long path wraps instead of widening the table
// beyond the page (a single name longer than a cell breaks anywhere: overflow-wrap in the style).
std::string path_cell(const std::string& path) {
  std::string escaped = html_escape(path);
  for (std::size_t at = escaped.find('/'); at != std::string::npos; at = escaped.find('/', at + 6)) escaped.insert(at + 1, "<wbr>");
  return "<td class=\"path\">" + escaped + "</td>";
}

// The document head with its style, the title line and the notes on the data.
void html_head(std::ostringstream& out, const AnalysisReport& report) {
  out << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
         "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; style-src 'unsafe-inline'; img-src data:\">\n"
         "<title>glarelab analysis</title>\n<style>\n"
         "body{font-family:sans-serif;margin:24px;max-width:1150px;color:#111}table{border-collapse:collapse;margin:8px 0}"
         "td,th{border:1px solid #bbb;padding:3px 8px;font-size:13px;text-align:left}th{background:#eee}td.path{overflow-wrap:anywhere}"
         "figure{display:inline-block;margin:8px}figcaption{font-size:12px;color:#444;max-width:560px}"
         ".note{color:#a00}\n</style></head><body>\n";
  out << "<h1>glarelab analysis</h1>\n<p>glarelab " << html_escape(software_version()) << "; "
      << report.data.sessions.size() << " session(s)";
  long trials = 0;
  for (const LoadedSession& s : report.data.sessions) trials += static_cast<long>(s.trials.size());
  out << ", " << trials << " trial(s). Tidy CSV: trials.csv, frames.csv, tracker_samples.csv.</p>\n";
  if (!report.data.notes.empty()) {
    out << "<h2>Notes on the data</h2>\n<div class=\"note\">";
    html_list(out, report.data.notes);
    out << "</div>\n";
  }
}

// One row per session, and a note for each aborted or unfinished one.
void html_sessions(std::ostringstream& out, const AnalysisReport& report) {
  out << "<h2>Sessions</h2>\n<table><tr><th>session</th><th>experiment</th><th>participant</th><th>status</th>"
         "<th>trials</th><th>started (UTC)</th><th>display</th><th>observer</th><th>observer's eye</th><th>software</th>"
         "<th>database</th></tr>\n";
  std::vector<std::string> session_notes;
  for (const LoadedSession& s : report.data.sessions) {
    out << "<tr>" << cell(std::to_string(s.record.id)) << cell(s.record.experiment) << cell(s.record.participant)
        << cell(s.record.status) << cell(std::to_string(s.trials.size())) << cell(s.record.started_utc)
        << cell(s.record.display_backend + " " + s.record.renderer) << cell(s.record.observer)
        << cell(observer_eye_text(s.record.config)) << cell(s.record.software_version) << path_cell(s.database) << "</tr>\n";
    if (s.record.status == "aborted") {
      session_notes.push_back("session " + s.label + " was aborted after " + std::to_string(s.trials.size()) +
                              " trial(s): its answered trials are included");
    } else if (s.record.status == "running") {
      session_notes.push_back("session " + s.label + " is still running or was killed: its committed trials are included");
    }
  }
  out << "</table>\n";
  html_list(out, session_notes);
}

// Percent correct of the scored forced-choice trials (graded ones too).
void html_scored(std::ostringstream& out, const AnalysisReport& report) {
  if (report.forced_choice.scored.empty()) return;
  out << "<p>Percent correct of the scored trials (the task had a right answer), with Clopper-Pearson 95% intervals:</p>\n";
  std::vector<std::string> lines;
  for (const ScoredShare& share : report.forced_choice.scored) lines.push_back(scored_sentence(share));
  html_list(out, lines);
}

// Preferences per group and pooled, the paired scales and the section's figures.
void html_forced_choice(std::ostringstream& out, const AnalysisReport& report) {
  out << "<h2>Forced choice</h2>\n<p>Relative frequency with which each option was chosen over the other with its "
         "Clopper-Pearson 95% interval, exact two-sided binomial test and, from 10 answers (expected counts of 5), "
         "Pearson chi-square test against no preference (Ritschel et al. 2009, Sec. 6.1).</p>\n";
  out << "<table><tr><th>group</th><th>preferred</th><th>other</th><th>chosen</th><th>of</th><th>share</th><th>95% CI</th>"
         "<th>chi-square</th><th>binomial</th><th>neither</th></tr>\n";
  for (const auto* list : {&report.forced_choice.groups, &report.forced_choice.pooled}) {
    for (const PairPreference& p : *list) {
      out << "<tr>" << cell(p.group) << cell(p.option_a) << cell(p.option_b) << cell(std::to_string(p.chose_a))
          << cell(std::to_string(p.chose_a + p.chose_b)) << cell(fixed(p.share_a(), 3))
          << cell(p.chose_a + p.chose_b > 0
                      ? fixed(p.share_a_interval.low, 3) + " to " + fixed(p.share_a_interval.high, 3)
                      : "-")
          << cell(describe(p.chi_square, "chi2")) << cell(describe_binomial(p.binomial))
          << cell(p.neither > 0 ? std::to_string(p.neither) + " (" + fixed(100.0 * p.neither_share(), 1) + "%)" : "0")
          << "</tr>\n";
    }
  }
  out << "</table>\n";
  html_scored(out, report);
  html_list(out, report.forced_choice.notes);
  out << paired_scales_html(report.paired_scales);
  html_figures(out, report, "forced_choice");
}

// Per track: reversal threshold, QUEST estimate and the psychometric fits.
void html_staircases(std::ostringstream& out, const AnalysisReport& report) {
  out << "<h2>Staircases and QUEST</h2>\n<p>Threshold as the mean intensity at the last " << report.options.last_reversals
      << " reversals; maximum-likelihood fits psi = gamma + (1 - gamma - lambda) F with lambda in [0, 0.06] and "
      << report.options.bootstrap_samples << " parametric bootstrap samples for the 95% intervals (Wichmann &amp; Hill 2001); the figures draw psignifit 4's "
         "Bayesian fit (Schuett et al. 2016: cumulative normal, the task's guess rate, lapse and overdispersion free), "
         "its threshold at F = 1/2 with the 95% credible interval.</p>\n";
  out << "<table><tr><th>participant</th><th>staircase</th><th>procedure</th><th>trials</th><th>reversals</th>"
         "<th>threshold (reversals)</th><th>QUEST estimate</th><th>fits</th></tr>\n";
  for (const StaircaseResult& s : report.staircases) {
    std::string threshold = s.reversal_threshold ? general(*s.reversal_threshold) + " (last " +
                                                       std::to_string(s.reversals_used) + ")"
                                                 : "-";
    if (!s.threshold_note.empty()) threshold += "; " + s.threshold_note;
    std::string fits;
    for (const PsychometricFit& fit : s.fits) fits += fit_sentence(fit) + "\n";
    if (s.psignifit) fits += "psignifit 4 (drawn): threshold " + general(s.psignifit->map[0]) + ", 95% " +
                             general(s.psignifit->intervals[0][0].low) + " to " + general(s.psignifit->intervals[0][0].high) + "\n";
    fits += s.psignifit_note.empty() ? "" : s.psignifit_note + "\n";
    if (!s.guess_note.empty()) fits += s.guess_note;
    out << "<tr>" << cell(s.participant_label) << cell(s.name) << cell(s.procedure) << cell(std::to_string(s.track.size()))
        << cell(std::to_string(s.reversals)) << cell(threshold)
        << cell(s.quest_estimate ? general(*s.quest_estimate) : "-") << "<td style=\"white-space:pre-line\">"
        << html_escape(fits) << "</td></tr>\n";
  }
  out << "</table>\n";
  html_figures(out, report, "staircase");
}

// Per track and per group x glare strength.
void html_pse(std::ostringstream& out, const AnalysisReport& report) {
  out << "<h2>Points of subjective equality</h2>\n<p>PSE: the comparison luminance (fraction of the display's peak) "
         "at which P(comparison brighter) crosses 1/2, from psignifit 4's posterior over every answer of the track that "
         "named a side (Schuett et al. 2016; cumulative normal, no guess or lapse rate, overdispersion free; 'neither' "
         "answers left out): its MAP threshold with the central 95% of the threshold's marginal, which exists also when "
         "the answers separate perfectly. Beside it, as a second opinion, the mean at the last "
      << report.options.last_reversals << " reversals. Per group and glare strength: the mean over participants (one "
         "participant: the credible interval; several: mean &plusmn; t SE).</p>\n";
  out << "<table><tr><th>participant</th><th>track</th><th>group</th><th>glare gain</th><th>reference</th><th>trials</th>"
         "<th>neither</th><th>PSE</th><th>95% interval</th><th>reversal mean</th></tr>\n";
  for (const PseTrack& t : report.pse.tracks) {
    out << "<tr>" << cell(t.participant_label) << cell(t.name) << cell(t.group) << cell(general(t.glare_gain))
        << cell(general(t.reference_fraction)) << cell(std::to_string(t.trials)) << cell(std::to_string(t.neither))
        << cell(t.pse_fraction ? general(*t.pse_fraction) + (t.note.empty() ? "" : "; " + t.note) : t.note)
        << cell(t.pse_interval ? general(t.pse_interval->low) + " to " + general(t.pse_interval->high) : "-")
        << cell(t.reversal_mean_fraction ? general(*t.reversal_mean_fraction) + " (last " +
                                               std::to_string(t.reversals_used) + ")"
                                         : "-")
        << "</tr>\n";
  }
  out << "</table>\n<table><tr><th>group</th><th>glare gain</th><th>participants</th><th>mean PSE</th>"
         "<th>95% interval</th></tr>\n";
  for (const PsePoint& p : report.pse.points) {
    out << "<tr>" << cell(p.group) << cell(general(p.glare_gain)) << cell(std::to_string(p.participants))
        << cell(general(p.mean_pse_fraction))
        << cell(p.interval ? general(p.interval->low) + " to " + general(p.interval->high) : "-") << "</tr>\n";
  }
  out << "</table>\n";
  html_figures(out, report, "pse");
}

// Perceived luminance per condition and target, the ANOVAs and paired t-tests.
void html_adjustments(std::ostringstream& out, const AnalysisReport& report) {
  const AdjustmentAnalysis& a = report.adjustments;
  out << "<h2>Double adjustment</h2>\n<p>Perceived luminance (mean of the adjusted spots), mean and standard error over "
         "participants (Ritschel et al. 2009, Fig. 12 right).</p>\n";
  out << "<table><tr><th>condition</th><th>target</th><th>mean</th><th>SE</th><th>participants</th></tr>\n";
  for (const AdjustmentCell& c : a.cells) {
    out << "<tr>" << cell(c.condition) << cell(c.target) << cell(general(c.perceived.mean))
        << cell(c.perceived.standard_error ? general(*c.perceived.standard_error) : "- (one participant)")
        << cell(std::to_string(c.perceived.n)) << "</tr>\n";
  }
  out << "</table>\n<ul>\n";
  for (const AdjustmentAnova& anova : a.anovas) {
    out << "<li>Repeated-measures ANOVA at target " << html_escape(anova.target) << ": "
        << html_escape(describe_anova(anova.anova)) << "</li>\n";
  }
  for (const PairedComparison& p : a.paired) {
    out << "<li>Paired t-test at target " << html_escape(p.target) << ", " << html_escape(p.condition_a) << " vs "
        << html_escape(p.condition_b) << ": " << html_escape(describe(p.t_test, "t")) << "</li>\n";
  }
  out << "</ul>\n";
  html_list(out, a.notes);
  html_figures(out, report, "adjustment");
}

// Frame timing per session and the response times.
void html_timing(std::ostringstream& out, const AnalysisReport& report) {
  out << "<h2>Timing quality</h2>\n<table><tr><th>session</th><th>status</th><th>clock</th><th>trials</th><th>frames</th>"
         "<th>dropped</th><th>onset jitter SD (ms)</th><th>max |onset error| (ms)</th><th>frame interval (ms)</th></tr>\n";
  for (const SessionTiming& t : report.timing.sessions) {
    out << "<tr>" << cell(t.label) << cell(t.status)
        << cell(t.clock == "virtual" ? "virtual: one refresh period per flip, so no frame can drop"
                                     : t.clock == "monotonic" ? "monotonic: the flips as they happened" : t.clock)
        << cell(std::to_string(t.trials)) << cell(std::to_string(t.frames))
        << cell(std::to_string(t.dropped) +
                (t.frames > 0 ? " (" + fixed(100.0 * static_cast<double>(t.dropped) / static_cast<double>(t.frames), 2) + "%)" : ""))
        << cell(t.onset_jitter_sd_s ? fixed(1000.0 * *t.onset_jitter_sd_s, 3) : "- (no frames)")
        << cell(t.onset_jitter_max_abs_s ? fixed(1000.0 * *t.onset_jitter_max_abs_s, 3) : "-")
        << cell(t.frame_interval_mean_s ? fixed(1000.0 * *t.frame_interval_mean_s, 3) + " +/- " +
                                              fixed(1000.0 * *t.frame_interval_sd_s, 3)
                                        : "-")
        << "</tr>\n";
  }
  out << "</table>\n";
  if (report.timing.response_time_median_s) {
    out << "<p>Response times: median " << fixed(*report.timing.response_time_median_s, 3) << " s, mean "
        << fixed(*report.timing.response_time_mean_s, 3) << " s over " << report.timing.response_times_s.size()
        << " answered trials.</p>\n";
  }
  html_figures(out, report, "timing");
}

// Samples, blinks and gaze-to-flip latency per session.
void html_tracker(std::ostringstream& out, const AnalysisReport& report) {
  out << "<h2>Tracker quality</h2>\n";
  if (report.tracker.sessions.empty()) {
    out << "<p>No tracker samples in these sessions.</p>\n";
  } else {
    out << "<table><tr><th>session</th><th>samples</th><th>valid</th><th>blinks</th><th>gaze to flip, live glare "
           "(median / 95th percentile / max ms, frames)</th></tr>\n";
    for (const SessionTracker& t : report.tracker.sessions) {
      const std::string latency =
          t.gaze_latency ? fixed(t.gaze_latency->median_ms, 1) + " / " + fixed(t.gaze_latency->p95_ms, 1) + " / " +
                               fixed(t.gaze_latency->max_ms, 1) + " (" + std::to_string(t.gaze_latency->frames) + ")"
                         : "no live glare frames";
      out << "<tr>" << cell(t.label) << cell(std::to_string(t.samples)) << cell(fixed(100.0 * t.valid_fraction(), 1) + "%")
          << cell(std::to_string(t.blinks)) << cell(latency) << "</tr>\n";
    }
    out << "</table>\n";
    html_figures(out, report, "tracker");
  }
}

}  // namespace

std::string render_html(const AnalysisReport& report) {
  std::ostringstream out;
  html_head(out, report);
  html_sessions(out, report);

  if (!report.forced_choice.empty()) {
    html_forced_choice(out, report);
  } else if (!report.forced_choice.scored.empty()) {
    out << "<h2>Percent correct</h2>\n";  // every scored trial is graded: no pair table
    html_scored(out, report);
  }

  if (!report.graded_choice.empty()) {
    out << graded_choice_html(report.graded_choice, report.options.bootstrap_samples);
    html_figures(out, report, "graded_choice");
  }

  if (!report.staircases.empty()) html_staircases(out, report);

  if (!report.quest_plus.empty()) {
    out << "<h2>QUEST+ and Psi posteriors</h2>\n<p>The posterior over each track's parameter grid after its last "
           "answered trial (Watson 2017), rebuilt by replaying the stored trials through the stored design: per "
           "parameter its value at the joint posterior mode, the marginal mean and SD; quest_plus_posteriors.csv holds "
           "every marginal.</p>\n";
    out << quest_plus_posteriors_html(report.quest_plus);
    html_figures(out, report, "quest_plus");
  }

  if (!report.straylight.empty()) {
    out << "<h2>Straylight</h2>\n<p>Each measurement's log(s) (deg^2/sr), the maximum of the likelihood of its answers "
           "recomputed from the stored trials, its ESD (the half-width of the likelihood at e^-1/2 of its peak) and the age norm "
           "log(s) = 0.87 + log10(1 + (age / 65)^4) (docs/STRAYLIGHT.md); straylight.csv holds them.</p>\n";
    out << straylight_measurements_html(report.straylight);
    html_figures(out, report, "straylight");
  }

  if (!report.pse.tracks.empty()) html_pse(out, report);

  if (!report.adjustments.empty()) html_adjustments(out, report);

  if (!report.ratings.empty()) {
    out << ratings_html(report.ratings);
    html_figures(out, report, "rating");
  }

  html_timing(out, report);
  html_tracker(out, report);
  out << "</body></html>\n";
  return out.str();
}

std::string render_terminal_summary(const AnalysisReport& report) {
  std::ostringstream out;
  long trials = 0;
  long aborted = 0;
  for (const LoadedSession& s : report.data.sessions) {
    trials += static_cast<long>(s.trials.size());
    aborted += s.record.status == "aborted" ? 1 : 0;
  }
  out << "Analysed " << report.data.sessions.size() << " session(s), " << trials << " trial(s)";
  if (aborted > 0) out << " (" << aborted << " aborted)";
  out << "\n";
  for (const std::string& note : report.data.notes) out << "  note: " << note << "\n";
  for (const PairPreference& p : report.forced_choice.pooled) out << "  forced choice " << preference_sentence(p) << "\n";
  for (const ScoredShare& s : report.forced_choice.scored) out << "  percent correct " << scored_sentence(s) << "\n";
  out << graded_choice_terminal(report.graded_choice);
  for (const StaircaseResult& s : report.staircases) {
    out << "  " << s.procedure << " " << s.participant_label << " " << s.name << ": ";
    if (s.reversal_threshold) {
      out << "threshold " << general(*s.reversal_threshold) << " (mean of last " << s.reversals_used << " reversals)";
    } else {
      out << s.threshold_note;
    }
    if (!s.fits.empty()) out << "; " << fit_sentence(s.fits.front());
    out << "\n";
  }
  out << quest_plus_posteriors_terminal(report.quest_plus);
  out << straylight_measurements_terminal(report.straylight);
  for (const PseTrack& t : report.pse.tracks) {
    out << "  pse " << t.participant_label << " " << t.name << " (glare gain " << general(t.glare_gain) << "): ";
    if (t.pse_fraction) {
      out << "PSE " << general(*t.pse_fraction) << " of peak";
      if (t.pse_interval) out << " [" << general(t.pse_interval->low) << ", " << general(t.pse_interval->high) << "]";
    }
    if (!t.note.empty()) out << (t.pse_fraction ? " (" + t.note + ")" : t.note);
    if (t.reversal_mean_fraction && !t.pse_from_reversals) out << "; reversal mean " << general(*t.reversal_mean_fraction);
    out << "\n";
  }
  for (const AdjustmentAnova& anova : report.adjustments.anovas) {
    out << "  adjustment at target " << anova.target << ": " << describe_anova(anova.anova) << "\n";
  }
  out << ratings_terminal(report.ratings);
  long frames = 0;
  long dropped = 0;
  std::set<std::string> clocks;
  for (const SessionTiming& t : report.timing.sessions) {
    frames += t.frames;
    dropped += t.dropped;
    if (!t.clock.empty()) clocks.insert(t.clock);
  }
  out << "  timing: " << frames << " frames, " << dropped << " dropped";
  // A virtual clock's flips are a period apart by construction: say which clock the count is on.
  if (!clocks.empty()) {
    std::string names;
    for (const std::string& clock : clocks) names += (names.empty() ? "" : " and ") + clock;
    out << " on the " << names << (clocks.size() > 1 ? " clocks" : " clock");
  }
  if (report.timing.response_time_median_s) out << "; median response time " << fixed(*report.timing.response_time_median_s, 3) << " s";
  out << "\n";
  return out.str();
}

namespace {

// The name the list of an analysis' outputs is kept under, in its folder.
constexpr const char* kManifestName = "manifest.txt";

// A manifest line glarelab may act on: a file name, or figures/ and a file name, of the characters
// its own outputs use. Anything else (an edited or planted manifest: "../x", "/etc/y") is ignored,
// so removing what a manifest lists never reaches outside the folder.
bool own_output_name(const std::string& line) {
  const std::string name = line.rfind("figures/", 0) == 0 ? line.substr(8) : line;
  if (name.empty() || name.front() == '.' || name == kManifestName) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
  });
}

std::vector<std::string> manifest_names(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  std::ifstream in(dir / kManifestName, std::ios::binary);
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (own_output_name(line)) names.push_back(line);
  }
  return names;
}

}  // namespace

std::vector<std::string> write_report(const AnalysisReport& report, const std::string& directory,
                                      std::optional<unsigned> mode) {
  const std::filesystem::path dir(directory);
  std::filesystem::create_directories(dir / "figures");
  const std::vector<std::string> previous = manifest_names(dir);
  std::vector<std::string> written = write_tidy_csv(report.data, directory, mode);
  auto write = [&](const std::filesystem::path& path, const std::string& content) {
    write_file_atomically(path.string(), content, mode);
    written.push_back(path.string());
  };
  if (!report.ratings.empty()) {
    write(dir / "ratings.csv", ratings_csv(report.ratings));
    write(dir / "rating_tests.csv", rating_tests_csv(report.ratings));
    const auto& comparisons = report.ratings.comparisons;
    if (std::any_of(comparisons.begin(), comparisons.end(), [](const RatingComparison& c) { return !c.post_hoc.empty(); }))
      write(dir / "rating_post_hoc.csv", rating_post_hoc_csv(report.ratings));
  }
  if (!report.quest_plus.empty()) write(dir / "quest_plus_posteriors.csv", quest_plus_posteriors_csv(report.quest_plus));
  if (!report.straylight.empty()) write(dir / "straylight.csv", straylight_measurements_csv(report.straylight));
  write(dir / "report.html", render_html(report));
  for (const Figure& figure : report.figures) write(dir / "figures" / (figure.file_stem + ".svg"), figure.svg);
  // The manifest names this analysis' files; what the previous one listed and this one did not
  // write goes, so the folder holds one analysis (a second database's report beside the first's
  // figures read as one report). Files glarelab did not list are left alone.
  std::set<std::string> current;
  std::string manifest;
  for (const std::string& path : written) {
    const std::string name = std::filesystem::path(path).lexically_relative(dir).generic_string();
    current.insert(name);
    manifest += name + "\n";
  }
  write_file_atomically((dir / kManifestName).string(), manifest, mode);
  for (const std::string& name : previous) {
    std::error_code ignored;
    if (current.count(name) == 0) std::filesystem::remove(dir / name, ignored);  // a link itself, not its target
  }
  return written;
}

}  // namespace glarelab::analysis

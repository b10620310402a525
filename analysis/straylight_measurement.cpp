#include "analysis/straylight_measurement.h"

#include <algorithm>
#include <sstream>

#include "analysis/analysis_report.h"
#include "analysis/report_numbers.h"
#include "analysis/svg_plot.h"
#include "analysis/tidy_csv.h"

namespace glarelab::analysis {
namespace {

std::string cell(const std::string& text) { return "<td>" + html_escape(text) + "</td>"; }

std::string flag_words(const StraylightMeasurement& m) {
  return m.unreliable ? "unreliable (a spread of the likelihood above " + fixed(m.esd_limit_log10, 2) + ")" : "reliable";
}

}  // namespace

std::string straylight_likelihood_svg(const StraylightMeasurement& m) {
  SvgPlot plot("Straylight likelihood: " + m.participant_label + ", " + m.eye + " eye (" + std::to_string(m.answers) +
                   " answers)",
               "log10(s) (deg^2/sr)", "normalised likelihood");
  // The window shows the estimate and the age norm with a margin of 0.4 log units.
  const double low = std::min(m.log_s, m.age_norm_log10) - 0.4, high = std::max(m.log_s, m.age_norm_log10) + 0.4;
  std::vector<double> x, y;
  for (std::size_t i = 0; i < m.grid_log_s.size() && i < m.likelihood.size(); ++i) {
    if (m.grid_log_s[i] < low || m.grid_log_s[i] > high) continue;
    x.push_back(m.grid_log_s[i]);
    y.push_back(m.likelihood[i]);
  }
  const double peak = y.empty() ? 1.0 : std::max(*std::max_element(y.begin(), y.end()), 1e-12) * 1.05;
  plot.set_x_range(low, high);
  plot.set_y_range(0.0, peak);
  if (x.size() > 1) plot.line(x, y, series_colour(0));
  plot.line({m.log_s, m.log_s}, {0.0, peak}, series_colour(0), 1.5, true);
  plot.line({m.age_norm_log10, m.age_norm_log10}, {0.0, peak}, series_colour(1), 1.5, true);
  plot.horizontal_error_bar(0.5 * peak, m.age_norm_log10 - m.age_norm_sd_log10, m.age_norm_log10 + m.age_norm_sd_log10,
                            series_colour(1));
  plot.legend("likelihood", series_colour(0));
  plot.legend("age norm +- population SD", series_colour(1));
  plot.note("log(s) " + fixed(m.log_s, 2) + ", ESD " + fixed(m.esd_log10, 3) + ": " + flag_words(m) + "; age norm " +
            fixed(m.age_norm_log10, 2) + " at " + general(m.age_years) + " years");
  return plot.svg();
}

std::string straylight_measurements_html(const std::vector<StraylightMeasurement>& measurements) {
  std::ostringstream out;
  out << "<table><tr><th>participant</th><th>eye</th><th>answers</th><th>log(s)</th><th>ESD</th><th>reliability</th>"
         "<th>age norm</th></tr>\n";
  for (const StraylightMeasurement& m : measurements)
    out << "<tr>" << cell(m.participant_label) << cell(m.eye) << cell(std::to_string(m.answers)) << cell(fixed(m.log_s, 2))
        << cell(fixed(m.esd_log10, 3)) << cell(flag_words(m))
        << cell(fixed(m.age_norm_log10, 2) + " (SD " + fixed(m.age_norm_sd_log10, 2) + ") at " + general(m.age_years) +
                " years")
        << "</tr>\n";
  out << "</table>\n";
  return out.str();
}

std::string straylight_measurements_terminal(const std::vector<StraylightMeasurement>& measurements) {
  std::ostringstream out;
  for (const StraylightMeasurement& m : measurements)
    out << "  straylight " << m.participant_label << " " << m.eye << " eye (" << m.answers << " answers): log(s) "
        << fixed(m.log_s, 2) << ", ESD " << fixed(m.esd_log10, 3) << ", " << flag_words(m) << "; age norm "
        << fixed(m.age_norm_log10, 2) << " at " << general(m.age_years) << " years\n";
  return out.str();
}

std::string straylight_measurements_csv(const std::vector<StraylightMeasurement>& measurements) {
  std::ostringstream out;
  out << "participant,eye,answers,log_s,esd_log10,reliable,age_years,age_norm_log10\r\n";
  for (const StraylightMeasurement& m : measurements)
    out << csv_field(m.participant_label) << ',' << csv_field(m.eye) << ',' << m.answers << ',' << csv_number(m.log_s)
        << ',' << csv_number(m.esd_log10) << ',' << (m.unreliable ? 0 : 1) << ',' << csv_number(m.age_years) << ','
        << csv_number(m.age_norm_log10) << "\r\n";
  return out.str();
}

void add_straylight_measurements(AnalysisReport& report, std::vector<StraylightMeasurement> measurements) {
  report.straylight = std::move(measurements);
  for (std::size_t i = 0; i < report.straylight.size(); ++i)
    report.figures.push_back({"straylight_" + std::to_string(i + 1), "straylight",
                              "Likelihood of the straylight log(s) from the answers of " +
                                  report.straylight[i].participant_label + ", with the age norm.",
                              straylight_likelihood_svg(report.straylight[i])});
}

}  // namespace glarelab::analysis

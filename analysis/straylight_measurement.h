#pragma once
// The straylight measurements of the loaded sessions (docs/STRAYLIGHT.md) as plain data for the
// report: the estimate log10(s), its ESD (the half-width of the likelihood at e^-1/2), the reliability
// flag, the participant's age norm beside it and the likelihood over its grid. The estimate is
// computed by the runner, which replays each session's stored answers through its stored design
// (runner/cli/straylight_measurements.h); this file only reports and draws it.
#include <string>
#include <vector>

namespace glarelab::analysis {

struct StraylightMeasurement {
  std::string participant_label;  // LoadedSession::label
  std::string eye;                // "left" or "right"
  int answers = 0;
  double log_s = 0.0;      // maximum of the likelihood, log10(deg^2 / sr)
  double esd_log10 = 0.0;  // expected SD
  bool unreliable = false;  // the ESD or the likelihood's SD above the limit
  double esd_limit_log10 = 0.0;  // the limit (0.08)
  double age_years = 0.0;  // the session's [observer] age_years
  double age_norm_log10 = 0.0;  // the healthy eye's log10(s) at that age
  double age_norm_sd_log10 = 0.0;  // the population's SD about it
  std::vector<double> grid_log_s;   // the likelihood's grid
  std::vector<double> likelihood;   // normalised to unit sum
};

// The figure of one measurement: its normalised likelihood over log(s) around the estimate, the
// estimate and the age norm (with its population SD) as vertical lines, ESD and flag in the note.
std::string straylight_likelihood_svg(const StraylightMeasurement& measurement);

// The report's table (one row per measurement), the terminal lines and the tidy CSV (RFC 4180 as
// analysis/tidy_csv.h, CRLF, numbers that read back exactly): participant, eye, answers, log_s,
// esd_log10, reliable, age_years, age_norm_log10.
std::string straylight_measurements_html(const std::vector<StraylightMeasurement>& measurements);
std::string straylight_measurements_terminal(const std::vector<StraylightMeasurement>& measurements);
std::string straylight_measurements_csv(const std::vector<StraylightMeasurement>& measurements);

}  // namespace glarelab::analysis

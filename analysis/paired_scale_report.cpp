#include "analysis/paired_scale_report.h"

#include <cstdio>
#include <sstream>

#include "analysis/report_numbers.h"
#include "analysis/svg_plot.h"

namespace glarelab::analysis {
namespace {

std::string cell(const std::string& text) { return "<td>" + html_escape(text) + "</td>"; }

}  // namespace

std::string paired_scales_html(const std::vector<PairedScale>& scales) {
  if (scales.empty()) return {};
  std::ostringstream out;
  out << "<h3>Bradley-Terry scale</h3>\n<p>Per pooled group, the options scaled so that P(i chosen over j) = "
         "pi_i / (pi_i + pi_j) (Bradley &amp; Terry 1952; maximum likelihood by Hunter's 2004 MM algorithm): log worth "
         "ln(pi_i / pi_ref) with its standard error from the Fisher information and the 95% Wald interval (&plusmn; 1.96 "
         "SE); worth pi_i / pi_ref.</p>\n";
  for (const PairedScale& paired : scales) {
    const BradleyTerryScale& s = paired.scale;
    out << "<p>" << html_escape(paired.group) << ":";
    if (!s.ok()) {
      out << " not computed (" << html_escape(s.unavailable) << ").</p>\n";
      continue;
    }
    out << " reference '" << html_escape(paired.options[s.reference]) << "', log likelihood " << fixed(s.log_likelihood, 2)
        << ".</p>\n<table><tr><th>option</th><th>log worth</th><th>SE</th><th>95% interval</th><th>worth</th></tr>\n";
    for (std::size_t i = 0; i < paired.options.size(); ++i) {
      const double half = 1.96 * s.standard_error[i];
      out << "<tr>" << cell(paired.options[i]) << cell(fixed(s.log_worth[i]))
          << cell(i == s.reference ? "- (reference)" : fixed(s.standard_error[i]))
          << cell(i == s.reference ? "-" : fixed(s.log_worth[i] - half) + " to " + fixed(s.log_worth[i] + half))
          << cell(fixed(s.worth[i])) << "</tr>\n";
    }
    out << "</table>\n";
  }
  return out.str();
}

}  // namespace glarelab::analysis

#include "analysis/paired_scale.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "analysis/report_numbers.h"

namespace glarelab::analysis {
namespace {

constexpr double kCharWidth_px = 7.0;  // a generous average advance of 11 px sans-serif

// White to a colour-blind-safe end (ColorBrewer PuOr: orange below 1/2, purple above), at most 70 %
// of the way so the black text on it stays legible.
std::string share_colour(double share) {
  const double t = std::clamp(std::abs(share - 0.5) * 2.0, 0.0, 1.0) * 0.7;
  const int end[3] = {share >= 0.5 ? 84 : 179, share >= 0.5 ? 39 : 88, share >= 0.5 ? 136 : 6};
  char text[8];
  std::snprintf(text, sizeof text, "#%02x%02x%02x", static_cast<int>(std::lround(255 + t * (end[0] - 255))),
                static_cast<int>(std::lround(255 + t * (end[1] - 255))), static_cast<int>(std::lround(255 + t * (end[2] - 255))));
  return text;
}

double text_width(const std::string& text) { return kCharWidth_px * static_cast<double>(text.size()); }

}  // namespace

std::vector<PairedScale> scale_pooled_pairs(const ForcedChoiceAnalysis& analysis) {
  std::map<std::string, std::vector<const PairPreference*>> by_group;
  std::vector<std::string> order;
  for (const PairPreference& p : analysis.pooled) {
    if (!by_group.contains(p.group)) order.push_back(p.group);
    by_group[p.group].push_back(&p);
  }
  std::vector<PairedScale> scales;
  for (const std::string& group : order) {
    PairedScale paired;
    paired.group = group;
    for (const PairPreference* p : by_group[group]) {
      for (const std::string* option : {&p->option_a, &p->option_b})
        if (std::find(paired.options.begin(), paired.options.end(), *option) == paired.options.end())
          paired.options.push_back(*option);
    }
    // A pairwise design compares every pair (Ritschel's all_pairs); a star of comparisons with one
    // reference (the demo's lamps) has no scale worth drawing.
    const std::size_t k = paired.options.size();
    if (k < 3 || by_group[group].size() != k * (k - 1) / 2) continue;
    std::sort(paired.options.begin(), paired.options.end());
    const auto index = [&](const std::string& option) {
      return static_cast<std::size_t>(std::find(paired.options.begin(), paired.options.end(), option) - paired.options.begin());
    };
    paired.wins.assign(paired.options.size(), std::vector<long>(paired.options.size(), 0));
    for (const PairPreference* p : by_group[group]) {
      paired.wins[index(p->option_a)][index(p->option_b)] += p->chose_a;
      paired.wins[index(p->option_b)][index(p->option_a)] += p->chose_b;
    }
    const auto control = std::find(paired.options.begin(), paired.options.end(), "control");
    const std::size_t reference = control != paired.options.end() ? index(*control) : 0;
    paired.scale = fit_bradley_terry(paired.options, paired.wins, reference);
    scales.push_back(std::move(paired));
  }
  return scales;
}

std::string preference_matrix_svg(const PairedScale& paired) {
  const std::size_t k = paired.options.size();
  double label_px = 0.0;
  for (const std::string& option : paired.options) label_px = std::max(label_px, text_width(option));
  const double cell_w = std::max(96.0, label_px + 16.0);
  const double cell_h = 40.0;
  const double left = 24.0 + label_px + 12.0;  // rotated axis title, then the row labels
  const double top = 64.0;                     // title, axis title, column labels
  const std::string title = "Preference matrix: " + paired.group;
  const double width = std::max(left + cell_w * static_cast<double>(k) + 16.0, text_width(title) + 24.0);
  const double height = top + cell_h * static_cast<double>(k) + 16.0;
  std::ostringstream out;
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height << "\" viewBox=\"0 0 "
      << width << " " << height << "\" font-family=\"sans-serif\" font-size=\"11\">\n";
  out << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  out << "<text x=\"" << width / 2 << "\" y=\"16\" text-anchor=\"middle\" font-size=\"13\" font-weight=\"bold\">"
      << html_escape(title) << "</text>\n";
  out << "<text x=\"" << left + cell_w * static_cast<double>(k) / 2 << "\" y=\"34\" text-anchor=\"middle\">"
      << "against (column)</text>\n";
  out << "<text transform=\"translate(14," << top + cell_h * static_cast<double>(k) / 2
      << ") rotate(-90)\" text-anchor=\"middle\">chosen (row)</text>\n";
  for (std::size_t j = 0; j < k; ++j) {
    out << "<text x=\"" << left + cell_w * (static_cast<double>(j) + 0.5) << "\" y=\"" << top - 8
        << "\" text-anchor=\"middle\">" << html_escape(paired.options[j]) << "</text>\n";
  }
  for (std::size_t i = 0; i < k; ++i) {
    const double y = top + cell_h * static_cast<double>(i);
    out << "<text x=\"" << left - 6 << "\" y=\"" << y + cell_h / 2 + 4 << "\" text-anchor=\"end\">"
        << html_escape(paired.options[i]) << "</text>\n";
    for (std::size_t j = 0; j < k; ++j) {
      const double x = left + cell_w * static_cast<double>(j);
      const long won = paired.wins[i][j];
      const long met = won + paired.wins[j][i];
      const bool shown = i != j && met > 0;
      const double share = shown ? static_cast<double>(won) / static_cast<double>(met) : 0.5;
      out << "<rect x=\"" << x << "\" y=\"" << y << "\" width=\"" << cell_w << "\" height=\"" << cell_h << "\" fill=\""
          << (i == j ? "#eeeeee" : share_colour(share)) << "\" stroke=\"#888\"/>\n";
      const std::string text = i == j ? "-" : met == 0 ? "not compared" : fixed(share, 2) + " (" + std::to_string(won) + "/" + std::to_string(met) + ")";
      out << "<text x=\"" << x + cell_w / 2 << "\" y=\"" << y + cell_h / 2 + 4 << "\" text-anchor=\"middle\">"
          << html_escape(text) << "</text>\n";
    }
  }
  out << "</svg>\n";
  return out.str();
}

std::string bradley_terry_svg(const PairedScale& paired) {
  const BradleyTerryScale& scale = paired.scale;
  const std::size_t k = paired.options.size();
  double label_px = 0.0;
  for (const std::string& option : paired.options) label_px = std::max(label_px, text_width(option));
  const double slot_px = std::max(90.0, label_px + 20.0);
  const std::string reference = paired.options.empty() ? "" : paired.options[std::min(scale.reference, k - 1)];
  SvgPlot plot("Bradley-Terry scale: " + paired.group, "option",
               "ln worth relative to " + reference,
               static_cast<int>(std::max(420.0, 80.0 + slot_px * static_cast<double>(k))), 320);
  plot.set_x_categories(paired.options);
  if (!scale.ok()) {
    plot.note("no scale: " + scale.unavailable);
    plot.set_y_range(-1.0, 1.0);
    return plot.svg();
  }
  double low = 0.0, high = 0.0;
  for (std::size_t i = 0; i < k; ++i) {
    low = std::min(low, scale.log_worth[i] - 1.96 * scale.standard_error[i]);
    high = std::max(high, scale.log_worth[i] + 1.96 * scale.standard_error[i]);
  }
  const double pad = 0.1 * std::max(high - low, 0.1);
  plot.set_y_range(low - pad, high + pad);
  plot.horizontal_rule(0.0, "#888");
  for (std::size_t i = 0; i < k; ++i) {
    const double x = static_cast<double>(i);
    if (scale.standard_error[i] > 0.0)
      plot.error_bar(x, scale.log_worth[i] - 1.96 * scale.standard_error[i], scale.log_worth[i] + 1.96 * scale.standard_error[i],
                     series_colour(1));
    plot.markers({x}, {scale.log_worth[i]}, series_colour(1), 5.0);
  }
  return plot.svg();
}

}  // namespace glarelab::analysis

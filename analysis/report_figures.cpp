// Figures of the analysis report (analysis/analysis_report.h), drawn with analysis/svg_plot.h.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "analysis/analysis_report.h"
#include "analysis/graded_choice_report.h"
#include "analysis/report_numbers.h"
#include "analysis/svg_plot.h"
#include "analysis/timing_figures.h"

namespace glarelab::analysis {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// "4", "3.5": a median or mean of ratings with at most 3 decimals and no trailing zeros.
std::string rating_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", value);
  std::string out = text;
  while (out.back() == '0') out.pop_back();
  if (out.back() == '.') out.pop_back();
  return out;
}

// A bar pair's label: the two options in the figure's fixed order, then the group's values without
// their keys ("control vs dynamic (lamp_130, brighter)"), so bars of one scene can be told apart
// and the label wraps at spaces within its slot.
std::string pair_label(const PairPreference& p, bool a_first, const FigureWords& words) {
  std::string values;
  std::size_t start = 0;
  while (start < p.group.size()) {
    std::size_t end = p.group.find(", ", start);
    if (end == std::string::npos) end = p.group.size();
    std::string part = p.group.substr(start, end - start);
    if (const std::size_t equals = part.find('='); equals != std::string::npos) part = part.substr(equals + 1);
    values += (values.empty() ? "" : ", ") + words.display(part);
    start = end + 2;
  }
  const std::string a = words.display(p.option_a), b = words.display(p.option_b);
  return (a_first ? a + " vs " + b : b + " vs " + a) + " (" + values + ")";
}

// Forced choice, Ritschel et al. 2009, Fig. 12 left: a bar pair per group and pair of options, at
// most kPairsPerFigure per figure (more make figures wider than the page), split evenly. Each
// option keeps one colour and one side in every pair (options in order of first appearance), so a
// colour means the same condition throughout, whichever option won a pair.
std::vector<Figure> forced_choice_figures(const ForcedChoiceAnalysis& analysis, const FigureWords& words) {
  constexpr std::size_t kPairsPerFigure = 8;
  const auto& rows = analysis.groups;
  std::vector<std::string> options;
  for (const PairPreference& p : rows)
    for (const std::string* option : {&p.option_a, &p.option_b})
      if (std::find(options.begin(), options.end(), *option) == options.end()) options.push_back(*option);
  const auto index_of = [&](const std::string& option) {
    return static_cast<std::size_t>(std::find(options.begin(), options.end(), option) - options.begin());
  };
  const std::size_t count = std::max<std::size_t>(1, (rows.size() + kPairsPerFigure - 1) / kPairsPerFigure);
  const std::size_t per_figure = std::max<std::size_t>(1, (rows.size() + count - 1) / count);
  std::vector<Figure> figures;
  for (std::size_t f = 0; f < count; ++f) {
    const std::size_t first = f * per_figure;
    const std::size_t last = std::min(rows.size(), first + per_figure);
    std::vector<std::string> labels;
    for (std::size_t i = first; i < last; ++i)
      labels.push_back(pair_label(rows[i], index_of(rows[i].option_a) < index_of(rows[i].option_b), words));
    SvgPlot plot("Forced choice: share choosing each option (95% Clopper-Pearson intervals)" +
                     (count > 1 ? " (" + std::to_string(f + 1) + " of " + std::to_string(count) + ")" : std::string()),
                 "pair of options (group)", "relative frequency (share of choices)",
                 std::max(560, 90 * static_cast<int>(last - first) + 80), 340);
    plot.set_x_categories(labels);
    plot.set_y_range(0.0, 1.0);
    plot.horizontal_rule(0.5, "#888");
    bool any_neither = false;
    std::vector<bool> shown(options.size(), false);
    for (std::size_t i = first; i < last; ++i) {
      const PairPreference& p = rows[i];
      const double x = static_cast<double>(i - first);
      const bool a_first = index_of(p.option_a) < index_of(p.option_b);
      const std::size_t left = index_of(a_first ? p.option_a : p.option_b);
      const std::size_t right = index_of(a_first ? p.option_b : p.option_a);
      const double share = a_first ? p.share_a() : 1.0 - p.share_a();
      plot.bar(x - 0.15, 0.3, share, series_colour(left));
      plot.bar(x + 0.15, 0.3, 1.0 - share, series_colour(right));
      shown[left] = shown[right] = true;
      if (p.chose_a + p.chose_b > 0) {
        const ProportionInterval& ci = p.share_a_interval;
        if (a_first) plot.error_bar(x - 0.15, ci.low, ci.high);
        else plot.error_bar(x - 0.15, 1.0 - ci.high, 1.0 - ci.low);
      }
      if (p.neither > 0) {
        any_neither = true;
        plot.markers({x}, {p.neither_share()}, "#000", 4.0);
      }
    }
    for (std::size_t o = 0; o < options.size(); ++o)
      if (shown[o]) plot.legend(words.display(options[o]), series_colour(o));
    if (any_neither) plot.legend("'neither' share (dot)", "#000");
    if (rows.empty()) plot.note("no forced-choice pairs to show");
    figures.push_back({f == 0 ? std::string("forced_choice") : "forced_choice_" + std::to_string(f + 1), "forced_choice",
                       "Relative frequency of choices per pair of options, one colour per option; the table names every group.",
                       plot.svg()});
  }
  return figures;
}

// The unit of a track's intensity (docs/PROCEDURES.md, adaptive trials): a staircase scales the
// comparison to a peak in cd/m2; QUEST runs on log10 cd/m2. (QUEST+ and Psi tracks are not
// staircases: their own section draws them in their own unit, analysis/quest_plus_posterior.h.)
std::string intensity_label(const StaircaseResult& s, const FigureWords& words) {
  if (!words.graded_label.empty() && s.procedure == "staircase")
    return words.graded_label + (words.graded_unit.empty() ? "" : " (" + words.graded_unit + ")");
  if (s.procedure == "staircase") return "comparison peak luminance (cd/m2)";
  return "stimulus luminance (log10 cd/m2)";
}

Figure staircase_track_figure(const StaircaseResult& s, std::size_t index, const FigureWords& words) {
  SvgPlot plot("Staircase track: " + s.participant_label + ", " + words.display(s.name), "trial", intensity_label(s, words));
  double low = kInf;
  double high = -kInf;
  std::vector<double> x, y, xc, yc, xi, yi, xr, yr;
  for (std::size_t i = 0; i < s.track.size(); ++i) {
    const StaircasePoint& p = s.track[i];
    low = std::min(low, p.intensity);
    high = std::max(high, p.intensity);
    x.push_back(static_cast<double>(i + 1));
    y.push_back(p.intensity);
    (p.correct ? xc : xi).push_back(static_cast<double>(i + 1));
    (p.correct ? yc : yi).push_back(p.intensity);
    if (p.reversal) {
      xr.push_back(static_cast<double>(i + 1));
      yr.push_back(p.intensity);
    }
  }
  if (s.track.empty()) {
    low = 0.0;
    high = 1.0;
    plot.note("no answered trials");
  }
  const double pad = 0.08 * (high - low);
  plot.set_x_range(0.0, static_cast<double>(s.track.size() + 1));
  plot.set_y_range(low - pad, high + pad);
  plot.line(x, y, "#999", 1.0);
  plot.markers(xr, yr, "#d00", 6.0, true);
  plot.markers(xc, yc, series_colour(0));
  plot.markers(xi, yi, series_colour(2), 3.5, true);
  if (s.reversal_threshold) plot.horizontal_rule(*s.reversal_threshold, "#d00");
  plot.legend("correct", series_colour(0));
  plot.legend("incorrect (hollow)", series_colour(2));
  plot.legend("reversal (ring)", "#d00");
  if (!s.threshold_note.empty()) plot.note(s.threshold_note);
  return {"staircase_" + std::to_string(index), "staircase", "Track of " + s.name + " (" + s.participant_label + ")",
          plot.svg()};
}

// A track's psychometric function as psignifit 4 fits it (StaircaseResult::psignifit; Schuett et
// al. 2016): the proportions per level (rings, area by trials), the MAP curve, and the threshold
// (F = 1/2) with its 95 % credible interval.
Figure psychometric_figure(const StaircaseResult& s, std::size_t index, const FigureWords& words) {
  SvgPlot plot("Psychometric function (psignifit 4): " + s.participant_label + ", " + words.display(s.name),
               intensity_label(s, words), "proportion correct");
  std::vector<std::pair<double, bool>> trials;
  for (const StaircasePoint& p : s.track) trials.emplace_back(p.intensity, p.correct);
  const auto levels = levels_from_trials(trials);
  double low = levels.empty() ? 0.0 : levels.front().intensity;
  double high = levels.empty() ? 1.0 : levels.back().intensity;
  const double pad = 0.1 * std::max(high - low, 1e-9);
  plot.set_x_range(low - pad, high + pad);
  plot.set_y_range(0.0, 1.0);
  std::vector<CountedPoint> points;
  for (const StimulusLevel& level : levels)
    points.push_back({level.intensity, static_cast<double>(level.correct) / static_cast<double>(level.trials), level.trials});
  counted_rings(plot, {points}, {"#333"});
  if (!s.psignifit) {
    plot.note(s.psignifit_note.empty() ? "no psignifit fit" : s.psignifit_note);
  } else {
    const PsignifitResult& fit = *s.psignifit;
    std::vector<double> cx, cy;
    for (int i = 0; i <= 120; ++i) {
      cx.push_back(low - pad + (high - low + 2 * pad) * i / 120.0);
      cy.push_back(psignifit_psi(fit.options, fit.map, cx.back()));
    }
    plot.line(cx, cy, series_colour(0), 2.0);
    const double threshold = fit.map[0];
    const double at = psignifit_psi(fit.options, fit.map, threshold);
    plot.horizontal_error_bar(at, fit.intervals[0][0].low, fit.intervals[0][0].high, series_colour(0));
    plot.markers({threshold}, {at}, series_colour(0), 4.5);
    plot.legend("MAP fit (cumulative normal)", series_colour(0));
    plot.legend("threshold " + general(threshold) + ", 95%: " + general(fit.intervals[0][0].low) + " to " +
                    general(fit.intervals[0][0].high),
                series_colour(0));
  }
  return {"psychometric_" + std::to_string(index), "staircase",
          "Proportion correct per intensity (rings, area by trials) with psignifit 4's fit of every trial of the track "
          "(MAP curve, guess rate " + general(s.guess_rate) + ", lapse and overdispersion free) and its threshold with "
          "the 95% credible interval (" + words.display(s.name) + ", " + s.participant_label + ")",
          plot.svg()};
}

Figure adjustment_figure(const AdjustmentAnalysis& a) {
  SvgPlot plot("Double adjustment: perceived luminance (mean +/- SE over participants)", "target intensity",
               "perceived luminance");
  plot.set_x_categories(a.targets);
  double high = 0.0;
  for (const AdjustmentCell& cell : a.cells) high = std::max(high, cell.perceived.mean + cell.perceived.standard_error.value_or(0.0));
  plot.set_y_range(0.0, high > 0.0 ? high * 1.1 : 1.0);
  const double width = 0.8 / static_cast<double>(std::max<std::size_t>(a.conditions.size(), 1));
  for (std::size_t c = 0; c < a.conditions.size(); ++c) {
    for (const AdjustmentCell& cell : a.cells) {
      if (cell.condition != a.conditions[c]) continue;
      const auto t = static_cast<double>(std::find(a.targets.begin(), a.targets.end(), cell.target) - a.targets.begin());
      const double x = t - 0.4 + width * (static_cast<double>(c) + 0.5);
      plot.bar(x, width * 0.9, cell.perceived.mean, series_colour(c));
      if (cell.perceived.standard_error) {
        plot.error_bar(x, cell.perceived.mean - *cell.perceived.standard_error,
                       cell.perceived.mean + *cell.perceived.standard_error);
      }
    }
    plot.legend(a.conditions[c], series_colour(c));
  }
  return {"adjustment", "adjustment", "Perceived luminance per condition and target intensity.", plot.svg()};
}

// Colour of answer value `index` of `count` (the scale's order): a diverging ramp from red (1,
// "completely different" in Luidolt 2020, Sec. 7.2.1) through yellow to blue (the top point,
// "exactly the same"), piecewise linear between five anchors after ColorBrewer's RdYlBu.
std::string rating_colour(std::size_t index, std::size_t count) {
  static const double anchors[5][3] = {{215, 25, 28}, {253, 174, 97}, {230, 216, 107}, {171, 217, 233}, {44, 123, 182}};
  const double t = count > 1 ? static_cast<double>(index) / static_cast<double>(count - 1) : 1.0;
  const double position = 4.0 * std::clamp(t, 0.0, 1.0);
  const auto low = static_cast<std::size_t>(std::min(3.0, std::floor(position)));
  const double w = position - static_cast<double>(low);
  char text[8];
  int rgb[3];
  for (int c = 0; c < 3; ++c) rgb[c] = static_cast<int>(std::lround((1.0 - w) * anchors[low][c] + w * anchors[low + 1][c]));
  std::snprintf(text, sizeof text, "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]);
  return text;
}

// Luidolt 2020, Figs. 7.2-7.7, one category: per condition a bar of its answers stacked by
// answer value (lowest at the bottom), and the median marked by a dot at half the answers: the
// segment under the dot is the median value (on a boundary when the median falls between two).
Figure rating_figure(const RatingAnalysis& ratings, const std::string& category, std::size_t index,
                     const FigureWords& words) {
  constexpr double kSlot_px = 110.0;
  std::vector<const RatingDistribution*> cells;
  for (const RatingDistribution& cell : ratings.cells)
    if (cell.category == category) cells.push_back(&cell);
  const std::string name = category.empty() ? "all trials" : words.display(category);
  SvgPlot plot("Ratings: " + name, "condition (median)", "answers",
               static_cast<int>(80.0 + kSlot_px * static_cast<double>(cells.size())), 340);
  std::vector<std::string> labels;
  long most = 1;
  for (const RatingDistribution* cell : cells) {
    const std::string condition = words.display(cell->condition);
    labels.push_back(cell->median ? condition + " (" + rating_number(*cell->median) + ")" : condition);
    most = std::max(most, cell->answers);
  }
  plot.set_x_categories(labels);  // the legend stands right of the plotting area (analysis/svg_plot.h)
  plot.set_y_range(0.0, static_cast<double>(most) * 1.1);
  const std::size_t points = ratings.scale.size();
  std::vector<double> median_x, median_y;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const auto& counts = cells[c]->categories;
    std::vector<long> cumulative(counts.size(), 0);
    long sum = 0;
    for (std::size_t v = 0; v < counts.size(); ++v) cumulative[v] = sum += counts[v].second;
    // Painted top segment first, each lower one over it: each value's colour shows from the
    // cumulative count below it to its own.
    for (std::size_t v = counts.size(); v-- > 0;) {
      if (counts[v].second == 0) continue;
      plot.bar(static_cast<double>(c), 0.6, static_cast<double>(cumulative[v]), rating_colour(v, points));
    }
    if (cells[c]->median) {
      median_x.push_back(static_cast<double>(c));
      median_y.push_back(0.5 * static_cast<double>(cells[c]->answers));
    }
  }
  plot.markers(median_x, median_y, "#000", 4.5);
  for (std::size_t v = points; v-- > 0;) plot.legend("answer " + ratings.scale[v], rating_colour(v, points));
  if (!median_x.empty()) plot.legend("median (dot)", "#000");
  if (cells.empty()) plot.note("no answered ratings");
  return {"rating_" + std::to_string(index), "rating",
          "Distribution of the ratings of " + name + " per condition (stacked by answer; dot: the median, also in "
          "brackets), as Luidolt (2020), Figs. 7.2-7.7.",
          plot.svg()};
}

// Luidolt 2020, Fig. 7.1: the mean rating of each category, a bar per condition.
Figure rating_means_figure(const RatingAnalysis& ratings, const FigureWords& words) {
  constexpr double kSlot_px = 120.0;
  std::vector<std::string> conditions;
  double top = 1.0;
  for (const RatingDistribution& cell : ratings.cells) {
    if (std::find(conditions.begin(), conditions.end(), cell.condition) == conditions.end())
      conditions.push_back(cell.condition);
  }
  for (const std::string& value : ratings.scale) top = std::max(top, std::strtod(value.c_str(), nullptr));
  std::vector<std::string> labels;
  for (const std::string& category : ratings.category_order)
    labels.push_back(category.empty() ? "all trials" : words.display(category));
  SvgPlot plot("Mean rating per category", "category", "mean rating",
               static_cast<int>(80.0 + kSlot_px * static_cast<double>(labels.size())), 320);
  plot.set_x_categories(labels);
  plot.set_y_range(0.0, top);
  const double width = 0.8 / static_cast<double>(std::max<std::size_t>(conditions.size(), 1));
  for (std::size_t c = 0; c < conditions.size(); ++c) {
    for (const RatingDistribution& cell : ratings.cells) {
      if (cell.condition != conditions[c] || !cell.mean) continue;
      const auto g = static_cast<double>(
          std::find(ratings.category_order.begin(), ratings.category_order.end(), cell.category) -
          ratings.category_order.begin());
      plot.bar(g - 0.4 + width * (static_cast<double>(c) + 0.5), width * 0.9, *cell.mean, series_colour(c));
    }
    plot.legend(words.display(conditions[c]), series_colour(c));
  }
  return {"rating_means", "rating",
          "Mean rating per category and condition (the scale's top is the axis' top), as Luidolt (2020), Fig. 7.1.",
          plot.svg()};
}

Figure pupil_figure(const SessionTracker& s, std::size_t index) {
  SvgPlot plot("Pupil diameter aligned to trial onset: " + s.label, "time from onset (s)", "pupil diameter (mm)");
  std::vector<double> x, y;
  double low = kInf;
  double high = -kInf;
  for (std::size_t i = 0; i < s.pupil.time_from_onset_s.size(); ++i) {
    if (!s.pupil.pupil_diameter_mm[i]) continue;
    x.push_back(s.pupil.time_from_onset_s[i]);
    y.push_back(*s.pupil.pupil_diameter_mm[i]);
    low = std::min(low, y.back());
    high = std::max(high, y.back());
  }
  if (x.empty()) {
    low = 0.0;
    high = 8.0;
    plot.note("no valid pupil samples around trial onsets");
  }
  plot.set_x_range(-0.5, 2.0);
  plot.set_y_range(low - 0.1 * (high - low) - 0.05, high + 0.1 * (high - low) + 0.05);
  plot.line(x, y, series_colour(1));
  return {"pupil_" + std::to_string(index), "tracker", "Mean pupil diameter around trial onsets (" + s.label + ")",
          plot.svg()};
}

}  // namespace

// Spencer et al. 1995, Figs. 12-13: perceived intensity (the PSE, % of the display's peak) against
// glare strength, one line per group (with and without context), and the reference's level dashed:
// where the line would lie if glare had no effect.
Figure pse_figure(const PseAnalysis& pse, const FigureWords& words) {
  SvgPlot plot("Perceived intensity against glare strength (95% intervals)", "glare strength (glare_gain)",
               "perceived intensity (% of display peak)", 620, 360);
  double x_low = kInf, x_high = -kInf, y_low = kInf, y_high = -kInf;
  for (const PsePoint& p : pse.points) {
    x_low = std::min(x_low, p.glare_gain), x_high = std::max(x_high, p.glare_gain);
    y_low = std::min(y_low, 100.0 * (p.interval ? p.interval->low : p.mean_pse_fraction));
    y_high = std::max(y_high, 100.0 * (p.interval ? p.interval->high : p.mean_pse_fraction));
  }
  if (pse.reference_fraction) {
    y_low = std::min(y_low, 100.0 * *pse.reference_fraction);
    y_high = std::max(y_high, 100.0 * *pse.reference_fraction);
  }
  if (pse.points.empty()) {
    plot.note("no PSE could be fitted");
    return {"pse", "pse", "Perceived intensity against glare strength.", plot.svg()};
  }
  const double x_pad = 0.05 * std::max(x_high - x_low, 1.0);
  plot.set_x_range(x_low - x_pad, x_high + x_pad);
  plot.set_y_range(std::max(0.0, y_low - 5.0), std::min(100.0, y_high + 5.0) + 1e-9);
  if (pse.reference_fraction) {
    plot.line({x_low - x_pad, x_high + x_pad}, {100.0 * *pse.reference_fraction, 100.0 * *pse.reference_fraction}, "#888",
              1.5, true);
    plot.legend("no glare effect (the glare image's maximum)", "#888");
  }
  std::vector<std::string> groups;
  for (const PsePoint& p : pse.points)
    if (std::find(groups.begin(), groups.end(), p.group) == groups.end()) groups.push_back(p.group);
  for (std::size_t g = 0; g < groups.size(); ++g) {
    std::vector<double> x, y;
    for (const PsePoint& p : pse.points) {
      if (p.group != groups[g]) continue;
      x.push_back(p.glare_gain);
      y.push_back(100.0 * p.mean_pse_fraction);
      if (p.interval) plot.error_bar(p.glare_gain, 100.0 * p.interval->low, 100.0 * p.interval->high, series_colour(g));
    }
    plot.line(x, y, series_colour(g));
    plot.markers(x, y, series_colour(g));
    plot.legend(groups[g].empty() ? "all trials" : words.display(groups[g]), series_colour(g));
  }
  return {"pse", "pse",
          "Point of subjective equality (comparison disc as bright as the glare image) against glare strength, per group; "
          "dashed: the glare image's maximum, where the points would lie if glare had no effect (Spencer et al. 1995, "
          "Figs. 12-13).",
          plot.svg()};
}

std::vector<Figure> draw_figures(const AnalysisReport& report) {
  std::vector<Figure> figures;
  if (!report.forced_choice.empty())
    for (Figure& figure : forced_choice_figures(report.forced_choice, report.options.words))
      figures.push_back(std::move(figure));
  for (std::size_t i = 0; i < report.paired_scales.size(); ++i) {
    const PairedScale& paired = report.paired_scales[i];
    figures.push_back({"preference_matrix_" + std::to_string(i + 1), "forced_choice",
                       "Share of choices of the row's option over the column's (" + paired.group + ").",
                       preference_matrix_svg(paired)});
    figures.push_back({"bradley_terry_" + std::to_string(i + 1), "forced_choice",
                       "Bradley-Terry scale of the options with 95% intervals (" + paired.group + ").",
                       bradley_terry_svg(paired)});
  }
  if (!report.graded_choice.empty()) figures.push_back(graded_choice_figure(report.graded_choice, report.options.words));
  for (std::size_t i = 0; i < report.staircases.size(); ++i) {
    figures.push_back(staircase_track_figure(report.staircases[i], i + 1, report.options.words));
    figures.push_back(psychometric_figure(report.staircases[i], i + 1, report.options.words));
  }
  if (!report.pse.tracks.empty()) figures.push_back(pse_figure(report.pse, report.options.words));
  if (!report.adjustments.empty()) figures.push_back(adjustment_figure(report.adjustments));
  if (!report.ratings.comparisons.empty()) figures.push_back(rating_means_figure(report.ratings, report.options.words));
  for (std::size_t i = 0; i < report.ratings.category_order.size(); ++i) {
    figures.push_back(rating_figure(report.ratings, report.ratings.category_order[i], i + 1, report.options.words));
  }
  for (Figure& figure : timing_figures(report.timing)) figures.push_back(std::move(figure));
  for (std::size_t i = 0; i < report.tracker.sessions.size(); ++i) {
    figures.push_back(pupil_figure(report.tracker.sessions[i], i + 1));
  }
  return figures;
}

}  // namespace glarelab::analysis

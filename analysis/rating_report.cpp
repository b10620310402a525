#include "analysis/rating_report.h"

#include <cctype>
#include <cstdio>
#include <sstream>
#include <vector>

#include "analysis/report_numbers.h"
#include "analysis/statistics.h"
#include "analysis/svg_plot.h"
#include "analysis/tidy_csv.h"

namespace glarelab::analysis {
namespace {

std::string distribution_text(const RatingDistribution& r) {
  std::string text;
  for (const auto& [value, count] : r.categories) text += (text.empty() ? "" : ", ") + value + ": " + std::to_string(count);
  return text;
}

std::string join(const std::vector<std::string>& items, const std::string& separator) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "" : separator) + item;
  return text;
}

// "glare appearance (control vs static vs dynamic): Friedman chi2(2) = 6.533, p = 0.0381,
// Kendall's W = 0.408; 8 participants, tie correction 0.9375 (fewer than 10 participants: ...)".
std::string comparison_sentence(const RatingComparison& c) {
  std::string text = (c.category.empty() ? std::string("all trials") : c.category) + " (" + join(c.conditions, " vs ") + "): ";
  if (!c.unavailable.empty()) {
    text += "not computed: " + c.unavailable;
  } else if (c.wilcoxon) {
    const WilcoxonSignedRank& w = *c.wilcoxon;
    if (!w.ok()) {
      text += "Wilcoxon signed-rank not computed: " + w.unavailable;
    } else {
      text += "Wilcoxon signed-rank T = " + general(w.statistic) + " (R+ " + general(w.rank_sum_positive) + ", R- " +
              general(w.rank_sum_negative) + "), " +
              (w.exact ? std::string("exact ") : "normal approximation z = " + fixed(w.z, 3) + ", ") + format_p(w.p_value);
      if (!w.exact && w.ranked < 10) text += " (fewer than 10 non-zero differences: the approximation is rough)";
      text += "; " + std::to_string(w.pairs) + " participants";
      if (w.zero_differences > 0) text += ", " + std::to_string(w.zero_differences) + " zero differences discarded";
    }
  } else if (c.friedman) {
    const FriedmanTest& f = *c.friedman;
    if (!f.ok()) {
      text += "Friedman test not computed: " + f.unavailable;
    } else {
      text += "Friedman chi2(" + general(f.df) + ") = " + fixed(f.chi_square, 3) + ", " + format_p(f.p_value) +
              ", Kendall's W = " + fixed(f.kendall_w, 3) + "; " + std::to_string(f.subjects) + " participants";
      if (f.tie_correction < 1.0) text += ", tie correction " + fixed(f.tie_correction, 4);
      // The chi-square approximation of the Friedman statistic is poor for small n (e.g. n = 3,
      // k = 3: chi2 = 6 has exact p = 0.028, chi-square p = 0.050).
      if (f.subjects < 10) text += " (fewer than 10 participants: the chi-square p is rough)";
    }
  }
  if (!c.left_out.empty()) text += "; left out (not every condition rated): " + join(c.left_out, ", ");
  return text;
}

// "real_lamp vs standard: Wilcoxon T = 0, exact p = 0.0156, Holm p = 0.0938" per pair after a
// significant Friedman test (analysis/rating_post_hoc.h).
std::string post_hoc_sentence(const RatingPairTest& pair) {
  const WilcoxonSignedRank& w = pair.wilcoxon;
  std::string text = pair.first + " vs " + pair.second + ": ";
  if (!w.ok()) return text + "not computed: " + w.unavailable;
  return text + "Wilcoxon T = " + general(w.statistic) + ", " + (w.exact ? "exact " : "normal approximation ") +
         format_p(w.p_value) + ", Holm p = " + fixed(pair.p_holm, 4);
}

std::string cell(const std::string& text) { return "<td>" + html_escape(text) + "</td>"; }

void html_list(std::ostringstream& out, const std::vector<std::string>& items) {
  if (items.empty()) return;
  out << "<ul>\n";
  for (const std::string& item : items) out << "<li>" << html_escape(item) << "</li>\n";
  out << "</ul>\n";
}

}  // namespace

std::string ratings_html(const RatingAnalysis& ratings) {
  std::ostringstream out;
  out << "<h2>Ratings</h2>\n<p>Answers per point of the scale, mean and median, per category (the question of the "
         "trial) and condition (Luidolt 2020, Sec. 7.2.1, Figs. 7.1-7.7). Per category, the conditions are compared on "
         "paired ratings (same participant, same category; a participant's repeated ratings of a condition averaged): "
         "two conditions by the Wilcoxon signed-rank test (zero differences discarded, tied differences midranked; "
         "exact p without zeros or ties and at most 50 pairs, else the normal approximation with the tie-corrected "
         "variance and no continuity correction), three or more by the Friedman test (midranks within each "
         "participant, tie-corrected) with Kendall's W = chi2 / (n (k - 1)).</p>\n";
  out << "<table><tr><th>category</th><th>condition</th><th>answers</th><th>distribution</th><th>mean</th>"
         "<th>median</th></tr>\n";
  for (const RatingDistribution& r : ratings.cells) {
    out << "<tr>" << cell(r.category.empty() ? "-" : r.category) << cell(r.condition) << cell(std::to_string(r.answers))
        << cell(distribution_text(r)) << cell(r.mean ? general(*r.mean) : "- (not numeric)")
        << cell(r.median ? general(*r.median) : "-") << "</tr>\n";
  }
  out << "</table>\n";
  if (!ratings.comparisons.empty()) {
    out << "<ul>\n";
    for (const RatingComparison& c : ratings.comparisons) {
      out << "<li>" << html_escape(comparison_sentence(c));
      if (!c.post_hoc.empty()) {
        out << "; pairs (Holm-adjusted):<ul>\n";
        for (const RatingPairTest& pair : c.post_hoc) out << "<li>" << html_escape(post_hoc_sentence(pair)) << "</li>\n";
        out << "</ul>";
      }
      out << "</li>\n";
    }
    out << "</ul>\n";
  }
  html_list(out, ratings.notes);
  out << "<p>Every category pooled:</p>\n<table><tr><th>condition</th><th>answers</th><th>distribution</th><th>mean</th>"
         "<th>median</th></tr>\n";
  for (const RatingDistribution& r : ratings.conditions) {
    out << "<tr>" << cell(r.condition) << cell(std::to_string(r.answers)) << cell(distribution_text(r))
        << cell(r.mean ? general(*r.mean) : "- (not numeric)") << cell(r.median ? general(*r.median) : "-") << "</tr>\n";
  }
  out << "</table>\n";
  return out.str();
}

std::string ratings_terminal(const RatingAnalysis& ratings) {
  std::ostringstream out;
  for (const RatingDistribution& r : ratings.conditions) {
    out << "  rating " << r.condition << ": " << r.answers << " answers";
    if (r.mean) out << ", mean " << general(*r.mean) << ", median " << general(*r.median);
    out << "\n";
  }
  for (const RatingComparison& c : ratings.comparisons) {
    out << "  rating test " << comparison_sentence(c) << "\n";
    for (const RatingPairTest& pair : c.post_hoc)
      out << "  rating post hoc " << (c.category.empty() ? std::string("all trials") : c.category) << ", "
          << post_hoc_sentence(pair) << "\n";
  }
  return out.str();
}

std::string ratings_csv(const RatingAnalysis& ratings) {
  std::string text = "category,condition,answers,mean,median";
  for (const std::string& value : ratings.scale) {
    std::string column = "answers_" + value;
    for (char& c : column)
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) c = '_';
    text += "," + csv_field(column);
  }
  text += "\r\n";
  for (const RatingDistribution& r : ratings.cells) {
    text += csv_field(r.category) + "," + csv_field(r.condition) + "," + std::to_string(r.answers) + "," +
            (r.mean ? csv_number(*r.mean) : "") + "," + (r.median ? csv_number(*r.median) : "");
    for (const auto& entry : r.categories) text += "," + std::to_string(entry.second);
    text += "\r\n";
  }
  return text;
}

std::string rating_tests_csv(const RatingAnalysis& ratings) {
  std::string text =
      "category,conditions,test,participants,zero_differences,statistic,df,z,p_value,kendall_w,method,not_computed\r\n";
  for (const RatingComparison& c : ratings.comparisons) {
    std::string row = csv_field(c.category) + "," + csv_field(join(c.conditions, ";")) + ",";
    if (c.wilcoxon) {
      const WilcoxonSignedRank& w = *c.wilcoxon;
      row += "wilcoxon_signed_rank," + std::to_string(w.pairs) + "," + std::to_string(w.zero_differences) + ",";
      if (w.ok()) {
        row += csv_number(w.statistic) + ",," + (w.exact ? "" : csv_number(w.z)) + "," + csv_number(w.p_value) + ",," +
               (w.exact ? "exact" : "normal") + ",";
      } else {
        row += ",,,,,," + csv_field(w.unavailable);
      }
    } else if (c.friedman) {
      const FriedmanTest& f = *c.friedman;
      row += "friedman," + std::to_string(f.subjects) + ",,";
      if (f.ok()) {
        row += csv_number(f.chi_square) + "," + csv_number(f.df) + ",," + csv_number(f.p_value) + "," +
               csv_number(f.kendall_w) + ",chi_square,";
      } else {
        row += ",,,,,," + csv_field(f.unavailable);
      }
    } else {
      row += "," + std::to_string(c.participants.size()) + ",,,,,,,," + csv_field(c.unavailable);
    }
    text += row + "\r\n";
  }
  return text;
}

std::string rating_post_hoc_csv(const RatingAnalysis& ratings) {
  std::string text = "category,first,second,participants,zero_differences,statistic,z,p_value,p_holm,method,not_computed\r\n";
  for (const RatingComparison& c : ratings.comparisons)
    for (const RatingPairTest& pair : c.post_hoc) {
      const WilcoxonSignedRank& w = pair.wilcoxon;
      text += csv_field(c.category) + "," + csv_field(pair.first) + "," + csv_field(pair.second) + "," +
              std::to_string(w.pairs) + "," + std::to_string(w.zero_differences) + ",";
      if (w.ok())
        text += csv_number(w.statistic) + "," + (w.exact ? "" : csv_number(w.z)) + "," + csv_number(w.p_value) + "," +
                csv_number(pair.p_holm) + "," + (w.exact ? "exact" : "normal") + ",\r\n";
      else
        text += ",,,,," + csv_field(w.unavailable) + "\r\n";
    }
  return text;
}

}  // namespace glarelab::analysis

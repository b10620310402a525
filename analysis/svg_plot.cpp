#include "analysis/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace glarelab::analysis {
namespace {

constexpr double kLeft_px = 64.0;
constexpr double kRight_px = 16.0;
constexpr double kTop_px = 40.0;
constexpr double kBottom_px = 48.0;

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", value);
  return text;
}

std::string tick_label(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", std::abs(value) < 1e-12 ? 0.0 : value);
  return text;
}

// "Nice" tick step (1, 2 or 5 times a power of ten) giving about five ticks.
double tick_step(double span) {
  const double raw = span / 5.0;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  const double ratio = raw / magnitude;
  return magnitude * (ratio < 1.5 ? 1.0 : ratio < 3.5 ? 2.0 : ratio < 7.5 ? 5.0 : 10.0);
}

constexpr double kFont_px = 11.0;
constexpr double kTitleFont_px = 13.0;
constexpr double kLineGap_px = 13.0;
constexpr double kTitleGap_px = 16.0;
constexpr double kLegendGap_px = 14.0;

// An upper estimate of a text's width in the figures' sans-serif: 0.62 em per character for
// normal text (DejaVu Sans, Chromium's usual sans-serif on Debian, averages about 0.55 em over
// lower-case text and digits), 0.66 em for the bold title.
double text_width(const std::string& text, double font_px) {
  std::size_t characters = 0;
  for (unsigned char c : text)
    if ((c & 0xC0) != 0x80) ++characters;  // count UTF-8 code points, not bytes
  return (font_px >= kTitleFont_px ? 0.66 : 0.62) * font_px * static_cast<double>(characters);
}

// Splits `text` into lines no wider than `width_px` at spaces (a word longer than the width
// gets a line of its own).
std::vector<std::string> wrap_text(const std::string& text, double width_px, double font_px) {
  std::vector<std::string> lines;
  std::string line;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find(' ', start);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(start, end - start);
    const std::string joined = line.empty() ? word : line + " " + word;
    if (!line.empty() && text_width(joined, font_px) > width_px) {
      lines.push_back(line);
      line = word;
    } else {
      line = joined;
    }
    start = end + 1;
  }
  lines.push_back(line);
  return lines;
}

void widen(double& low, double& high) {
  if (!std::isfinite(low) || !std::isfinite(high)) {
    low = 0.0;
    high = 1.0;
  }
  if (high - low < 1e-12 * std::max(1.0, std::abs(low))) {
    const double pad = std::max(0.5, std::abs(low) * 0.1);
    low -= pad;
    high += pad;
  }
}

}  // namespace

std::string html_escape(const std::string& text) {
  std::string escaped;
  escaped.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': escaped += "&amp;"; break;
      case '<': escaped += "&lt;"; break;
      case '>': escaped += "&gt;"; break;
      case '"': escaped += "&quot;"; break;
      case '\'': escaped += "&#39;"; break;
      default: escaped += c;
    }
  }
  return escaped;
}

const std::string& series_colour(std::size_t index) {
  // Okabe & Ito (2008), "Color universal design": distinguishable with every common colour-vision
  // deficiency.
  static const std::vector<std::string> colours = {"#0072b2", "#e69f00", "#009e73", "#cc79a7", "#56b4e9", "#d55e00"};
  return colours[index % colours.size()];
}

SvgPlot::SvgPlot(std::string title, std::string x_label, std::string y_label, int width_px, int height_px)
    : title_(std::move(title)), x_label_(std::move(x_label)), y_label_(std::move(y_label)), width_px_(width_px),
      height_px_(height_px) {}

void SvgPlot::set_x_range(double low, double high) {
  widen(low, high);
  x_low_ = low;
  x_high_ = high;
}

void SvgPlot::set_y_range(double low, double high) {
  widen(low, high);
  y_low_ = low;
  y_high_ = high;
}

void SvgPlot::set_x_categories(std::vector<std::string> names) {
  categories_ = std::move(names);
  // Each slot at least as wide as the longest word of its label (labels wrap at spaces), so the
  // figure's width follows the number of categories and no label runs into the next.
  double word_px = 0.0;
  for (const std::string& name : categories_) {
    std::size_t start = 0;
    while (start <= name.size()) {
      std::size_t end = name.find(' ', start);
      if (end == std::string::npos) end = name.size();
      word_px = std::max(word_px, text_width(name.substr(start, end - start), kFont_px));
      start = end + 1;
    }
  }
  const double needed = kLeft_px + kRight_px + (word_px + 12.0) * static_cast<double>(std::max<std::size_t>(categories_.size(), 1));
  width_px_ = std::max(width_px_, static_cast<int>(std::ceil(needed)));
  x_low_ = -0.5;
  x_high_ = static_cast<double>(std::max<std::size_t>(categories_.size(), 1)) - 0.5;
}

double SvgPlot::px_x(double x) const {
  return kLeft_px + (x - x_low_) / (x_high_ - x_low_) * (width_px_ - kLeft_px - kRight_px);
}

double SvgPlot::px_y(double y) const {
  return height_px_ - kBottom_px - (y - y_low_) / (y_high_ - y_low_) * (height_px_ - kTop_px - kBottom_px);
}

void SvgPlot::line(const std::vector<double>& x, const std::vector<double>& y, const std::string& colour, double width_px,
                   bool dashed) {
  std::string points;
  for (std::size_t i = 0; i < std::min(x.size(), y.size()); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i])) continue;
    points += number(px_x(x[i])) + "," + number(px_y(y[i])) + " ";
  }
  if (points.empty()) return;
  body_ += "<polyline fill=\"none\" stroke=\"" + colour + "\" stroke-width=\"" + number(width_px) + "\"" +
           (dashed ? " stroke-dasharray=\"5,4\"" : "") + " points=\"" + points + "\"/>\n";
}

void SvgPlot::markers(const std::vector<double>& x, const std::vector<double>& y, const std::string& colour,
                      double radius_px, bool hollow) {
  for (std::size_t i = 0; i < std::min(x.size(), y.size()); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i])) continue;
    body_ += "<circle cx=\"" + number(px_x(x[i])) + "\" cy=\"" + number(px_y(y[i])) + "\" r=\"" + number(radius_px) +
             "\" " + (hollow ? "fill=\"white\" stroke=\"" + colour + "\" stroke-width=\"1.5\"" : "fill=\"" + colour + "\"") +
             "/>\n";
  }
}

void SvgPlot::bar(double x_centre, double width, double y, const std::string& colour) {
  const double base = px_y(std::clamp(0.0, y_low_, y_high_));
  const double top = px_y(y);
  const double left = px_x(x_centre - width / 2.0);
  const double right = px_x(x_centre + width / 2.0);
  body_ += "<rect x=\"" + number(left) + "\" y=\"" + number(std::min(base, top)) + "\" width=\"" + number(right - left) +
           "\" height=\"" + number(std::abs(base - top)) + "\" fill=\"" + colour + "\"/>\n";
}

void SvgPlot::error_bar(double x, double low, double high, const std::string& colour) {
  const double lowest = std::min(y_low_, y_high_), highest = std::max(y_low_, y_high_);
  const double y0 = px_y(std::clamp(low, lowest, highest));
  const double y1 = px_y(std::clamp(high, lowest, highest));
  const double cx = px_x(x);
  // A cap where the interval ends; an arrowhead (pointing away from the middle) where the plot cuts
  // it. `outward` is the arrow's direction in pixels (+1: down the page).
  const auto end = [&](double y, bool clipped, double outward) {
    if (clipped) return "M" + number(cx - 4.0) + "," + number(y - 6.0 * outward) + "L" + number(cx) + "," + number(y) + "L" +
                        number(cx + 4.0) + "," + number(y - 6.0 * outward);
    return "M" + number(cx - 5.0) + "," + number(y) + "H" + number(cx + 5.0);
  };
  body_ += "<path fill=\"none\" stroke=\"" + colour + "\" stroke-width=\"1.5\" d=\"M" + number(cx) + "," + number(y0) + "V" +
           number(y1) + end(y0, low < lowest, 1.0) + end(y1, high > highest, -1.0) + "\"/>\n";
}

void SvgPlot::horizontal_error_bar(double y, double low, double high, const std::string& colour) {
  const double x0 = px_x(std::clamp(low, x_low_, x_high_));
  const double x1 = px_x(std::clamp(high, x_low_, x_high_));
  const double cy = px_y(y);
  const auto end = [&](double x, bool clipped, double outward) {
    if (clipped) return "M" + number(x - 6.0 * outward) + "," + number(cy - 4.0) + "L" + number(x) + "," + number(cy) + "L" +
                        number(x - 6.0 * outward) + "," + number(cy + 4.0);
    return "M" + number(x) + "," + number(cy - 5.0) + "V" + number(cy + 5.0);
  };
  body_ += "<path fill=\"none\" stroke=\"" + colour + "\" stroke-width=\"1.5\" d=\"M" + number(x0) + "," + number(cy) + "H" +
           number(x1) + end(x0, low < x_low_, -1.0) + end(x1, high > x_high_, 1.0) + "\"/>\n";
}

void SvgPlot::horizontal_rule(double y, const std::string& colour) {
  body_ += "<line x1=\"" + number(kLeft_px) + "\" x2=\"" + number(width_px_ - kRight_px) + "\" y1=\"" + number(px_y(y)) +
           "\" y2=\"" + number(px_y(y)) + "\" stroke=\"" + colour + "\" stroke-dasharray=\"3,3\"/>\n";
}

double SvgPlot::px_per_x() const { return (width_px_ - kLeft_px - kRight_px) / (x_high_ - x_low_); }

double counted_rings(SvgPlot& plot, const std::vector<std::vector<CountedPoint>>& series,
                     const std::vector<std::string>& colours) {
  std::vector<double> xs;
  long most = 1;
  for (const auto& points : series)
    for (const CountedPoint& p : points) {
      xs.push_back(p.x);
      most = std::max(most, p.trials);
    }
  std::sort(xs.begin(), xs.end());
  double gap_px = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < xs.size(); ++i)
    if (xs[i] > xs[i - 1]) gap_px = std::min(gap_px, (xs[i] - xs[i - 1]) * plot.px_per_x());
  const double count = static_cast<double>(std::max<std::size_t>(series.size(), 1));
  // Side by side at one x the series span count (2 r + 1) px, which must fit in the gap to the next x.
  const double r_max = std::clamp((gap_px / count - 1.0) / 2.0, 2.0, 8.0);
  for (std::size_t s = 0; s < series.size(); ++s) {
    const double shift_px = (static_cast<double>(s) - 0.5 * (count - 1.0)) * (2.0 * r_max + 1.0);
    for (const CountedPoint& p : series[s]) {
      const double radius = std::max(1.5, r_max * std::sqrt(static_cast<double>(p.trials) / static_cast<double>(most)));
      plot.markers({p.x + shift_px / plot.px_per_x()}, {p.y}, colours[s % colours.size()], radius, true);
    }
  }
  return r_max;
}

void SvgPlot::legend(const std::string& label, const std::string& colour) { legend_.emplace_back(label, colour); }

void SvgPlot::note(const std::string& text) { notes_.push_back(text); }

std::string SvgPlot::svg() const {
  // Layout: the plotting area keeps the geometry the drawing calls used (kLeft_px, kTop_px, ...);
  // everything around it is measured from estimated text widths and the area is moved (one
  // translate) when the title, notes or tick labels need more room. The legend stands right of
  // the plotting area, never over the data; the figure grows to hold it.
  const double plot_w = width_px_ - kLeft_px - kRight_px;
  const double plot_h = height_px_ - kTop_px - kBottom_px;

  // Y ticks and their widest label.
  std::vector<std::pair<double, std::string>> y_ticks;
  const double y_step = tick_step(y_high_ - y_low_);
  for (double tick = std::ceil(y_low_ / y_step) * y_step; tick <= y_high_ + 1e-9 * y_step; tick += y_step)
    y_ticks.emplace_back(px_y(tick), tick_label(tick));
  double tick_w = 0.0;
  for (const auto& tick : y_ticks) tick_w = std::max(tick_w, text_width(tick.second, kFont_px));
  const std::vector<std::string> y_lines = wrap_text(y_label_, plot_h, kFont_px);
  const double y_label_w = kLineGap_px * static_cast<double>(y_lines.size());
  // The y label's lines are vertical baselines at x = 14, 27, ... (glyphs reach about 9 px left
  // of a baseline and 3 px right of it); the tick labels end 6 px left of the plotting area.
  const double left_needed = 14.0 + y_label_w - kLineGap_px + 6.0 + tick_w + 6.0;
  const double dx = std::max(0.0, std::ceil(left_needed - kLeft_px));

  double legend_w = 0.0;
  for (const auto& entry : legend_) legend_w = std::max(legend_w, 14.0 + text_width(entry.first, kFont_px));
  const double legend_block = legend_.empty() ? 0.0 : legend_w + kLegendGap_px;
  const double width = dx + width_px_ + legend_block;

  const std::vector<std::string> title_lines = wrap_text(title_, width - 16.0, kTitleFont_px);
  std::vector<std::string> note_lines;
  for (const std::string& note : notes_)
    for (const std::string& line : wrap_text(note, width - 16.0, kFont_px)) note_lines.push_back(line);
  const double header_bottom =
      16.0 + kTitleGap_px * static_cast<double>(title_lines.size() - 1) + 14.0 * static_cast<double>(note_lines.size());
  const double dy = std::max(0.0, std::ceil(header_bottom + 10.0 - kTop_px));

  // Category labels wrapped to their slot (set_x_categories made the slots wide enough for the
  // longest word).
  std::vector<std::vector<std::string>> category_lines;
  std::size_t most_lines = 1;
  const double slot = categories_.empty() ? plot_w : plot_w / (x_high_ - x_low_);
  for (const std::string& name : categories_) {
    category_lines.push_back(wrap_text(name, slot - 6.0, kFont_px));
    most_lines = std::max(most_lines, category_lines.back().size());
  }
  const std::vector<std::string> x_lines = wrap_text(x_label_, width - 16.0, kFont_px);
  const double legend_h = 14.0 * static_cast<double>(legend_.size()) + 8.0;
  const double below = kLineGap_px * static_cast<double>(most_lines - 1) + kLineGap_px * static_cast<double>(x_lines.size() - 1);
  const double height = std::max(dy + height_px_ + below, dy + kTop_px + legend_h + 8.0);

  std::ostringstream out;
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height << "\" viewBox=\"0 0 "
      << width << " " << height << "\" font-family=\"sans-serif\" font-size=\"11\">\n";
  out << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  for (std::size_t i = 0; i < title_lines.size(); ++i) {
    out << "<text x=\"" << width / 2 << "\" y=\"" << 16.0 + kTitleGap_px * static_cast<double>(i)
        << "\" text-anchor=\"middle\" font-size=\"13\" font-weight=\"bold\">" << html_escape(title_lines[i]) << "</text>\n";
  }
  for (std::size_t i = 0; i < note_lines.size(); ++i) {
    out << "<text x=\"" << width / 2 << "\" y=\""
        << 16.0 + kTitleGap_px * static_cast<double>(title_lines.size() - 1) + 14.0 * static_cast<double>(i + 1)
        << "\" text-anchor=\"middle\" fill=\"#a00\">" << html_escape(note_lines[i]) << "</text>\n";
  }
  const bool moved = dx > 0.0 || dy > 0.0;
  if (moved) out << "<g transform=\"translate(" << dx << "," << dy << ")\">\n";
  const double plot_left = kLeft_px;
  const double plot_right = width_px_ - kRight_px;
  const double plot_top = kTop_px;
  const double plot_bottom = height_px_ - kBottom_px;
  out << "<rect class=\"plot-area\" x=\"" << plot_left << "\" y=\"" << plot_top << "\" width=\"" << plot_right - plot_left
      << "\" height=\"" << plot_bottom - plot_top << "\" fill=\"none\" stroke=\"#444\"/>\n";
  for (const auto& [y, label] : y_ticks) {
    out << "<line x1=\"" << plot_left - 4 << "\" x2=\"" << plot_left << "\" y1=\"" << number(y) << "\" y2=\"" << number(y)
        << "\" stroke=\"#444\"/><text x=\"" << plot_left - 6 << "\" y=\"" << number(y + 4) << "\" text-anchor=\"end\">"
        << label << "</text>\n";
  }
  if (categories_.empty()) {
    const double x_step = tick_step(x_high_ - x_low_);
    // Numeric labels 18 px below the axis: clear of the lowest y tick label, which ends about 7 px
    // below the axis when that tick sits on it.
    for (double tick = std::ceil(x_low_ / x_step) * x_step; tick <= x_high_ + 1e-9 * x_step; tick += x_step) {
      out << "<line x1=\"" << number(px_x(tick)) << "\" x2=\"" << number(px_x(tick)) << "\" y1=\"" << plot_bottom
          << "\" y2=\"" << plot_bottom + 4 << "\" stroke=\"#444\"/><text x=\"" << number(px_x(tick)) << "\" y=\""
          << plot_bottom + 18 << "\" text-anchor=\"middle\">" << tick_label(tick) << "</text>\n";
    }
  } else {
    for (std::size_t i = 0; i < categories_.size(); ++i) {
      const std::string x = number(px_x(static_cast<double>(i)));
      out << "<text x=\"" << x << "\" y=\"" << plot_bottom + 16 << "\" text-anchor=\"middle\">";
      if (category_lines[i].size() == 1) {  // one line: plain text, as the figure tests read it
        out << html_escape(category_lines[i][0]) << "</text>\n";
        continue;
      }
      for (std::size_t line = 0; line < category_lines[i].size(); ++line) {
        out << "<tspan x=\"" << x << "\"" << (line == 0 ? "" : " dy=\"" + number(kLineGap_px) + "\"") << ">"
            << html_escape(category_lines[i][line]) << "</tspan>";
      }
      out << "</text>\n";
    }
  }
  const double x_label_y = height_px_ - 8 + kLineGap_px * static_cast<double>(most_lines - 1);
  for (std::size_t i = 0; i < x_lines.size(); ++i) {
    out << "<text x=\"" << (plot_left + plot_right) / 2 << "\" y=\"" << x_label_y + kLineGap_px * static_cast<double>(i)
        << "\" text-anchor=\"middle\">" << html_escape(x_lines[i]) << "</text>\n";
  }
  for (std::size_t i = 0; i < y_lines.size(); ++i) {
    const double x = 14.0 + kLineGap_px * static_cast<double>(i) - dx;
    out << "<text transform=\"translate(" << number(x) << ","
        << (plot_top + plot_bottom) / 2 << ") rotate(-90)\" text-anchor=\"middle\">" << html_escape(y_lines[i])
        << "</text>\n";
  }
  out << "<g class=\"data\">\n" << body_ << "</g>\n";
  if (!legend_.empty()) {
    out << "<g class=\"legend\">\n";
    const double x0 = plot_right + kLegendGap_px;
    for (std::size_t i = 0; i < legend_.size(); ++i) {
      const double y = plot_top + 14 + 14 * static_cast<double>(i);
      out << "<rect x=\"" << x0 << "\" y=\"" << y - 9 << "\" width=\"10\" height=\"10\" fill=\"" << legend_[i].second
          << "\"/><text x=\"" << x0 + 14 << "\" y=\"" << y << "\">" << html_escape(legend_[i].first) << "</text>\n";
    }
    out << "</g>\n";
  }
  if (moved) out << "</g>\n";
  out << "</svg>\n";
  return out.str();
}

}  // namespace glarelab::analysis

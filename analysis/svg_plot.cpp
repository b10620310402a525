#include "analysis/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
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
  static const std::vector<std::string> colours = {"#1b9e77", "#386cb0", "#d95f02", "#7570b3", "#e7298a", "#66a61e"};
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
  const std::string cx = number(px_x(x));
  const std::string left = number(px_x(x) - 5.0);
  const std::string right = number(px_x(x) + 5.0);
  const std::string y0 = number(px_y(low));
  const std::string y1 = number(px_y(high));
  body_ += "<path fill=\"none\" stroke=\"" + colour + "\" stroke-width=\"1.5\" d=\"M" + cx + "," + y0 + "V" + y1 + "M" +
           left + "," + y0 + "H" + right + "M" + left + "," + y1 + "H" + right + "\"/>\n";
}

void SvgPlot::horizontal_rule(double y, const std::string& colour) {
  body_ += "<line x1=\"" + number(kLeft_px) + "\" x2=\"" + number(width_px_ - kRight_px) + "\" y1=\"" + number(px_y(y)) +
           "\" y2=\"" + number(px_y(y)) + "\" stroke=\"" + colour + "\" stroke-dasharray=\"3,3\"/>\n";
}

void SvgPlot::legend(const std::string& label, const std::string& colour) { legend_.emplace_back(label, colour); }

void SvgPlot::note(const std::string& text) { notes_.push_back(text); }

std::string SvgPlot::svg() const {
  std::ostringstream out;
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width_px_ << "\" height=\"" << height_px_
      << "\" viewBox=\"0 0 " << width_px_ << " " << height_px_ << "\" font-family=\"sans-serif\" font-size=\"11\">\n";
  out << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  out << "<text x=\"" << width_px_ / 2 << "\" y=\"16\" text-anchor=\"middle\" font-size=\"13\" font-weight=\"bold\">"
      << html_escape(title_) << "</text>\n";
  for (std::size_t i = 0; i < notes_.size(); ++i) {
    out << "<text x=\"" << width_px_ / 2 << "\" y=\"" << 30 + 12 * i << "\" text-anchor=\"middle\" fill=\"#a00\">"
        << html_escape(notes_[i]) << "</text>\n";
  }
  const double plot_left = kLeft_px;
  const double plot_right = width_px_ - kRight_px;
  const double plot_top = kTop_px;
  const double plot_bottom = height_px_ - kBottom_px;
  out << "<rect x=\"" << plot_left << "\" y=\"" << plot_top << "\" width=\"" << plot_right - plot_left << "\" height=\""
      << plot_bottom - plot_top << "\" fill=\"none\" stroke=\"#444\"/>\n";
  // y ticks
  const double y_step = tick_step(y_high_ - y_low_);
  for (double tick = std::ceil(y_low_ / y_step) * y_step; tick <= y_high_ + 1e-9 * y_step; tick += y_step) {
    out << "<line x1=\"" << plot_left - 4 << "\" x2=\"" << plot_left << "\" y1=\"" << number(px_y(tick)) << "\" y2=\""
        << number(px_y(tick)) << "\" stroke=\"#444\"/><text x=\"" << plot_left - 6 << "\" y=\"" << number(px_y(tick) + 4)
        << "\" text-anchor=\"end\">" << tick_label(tick) << "</text>\n";
  }
  if (categories_.empty()) {
    const double x_step = tick_step(x_high_ - x_low_);
    for (double tick = std::ceil(x_low_ / x_step) * x_step; tick <= x_high_ + 1e-9 * x_step; tick += x_step) {
      out << "<line x1=\"" << number(px_x(tick)) << "\" x2=\"" << number(px_x(tick)) << "\" y1=\"" << plot_bottom
          << "\" y2=\"" << plot_bottom + 4 << "\" stroke=\"#444\"/><text x=\"" << number(px_x(tick)) << "\" y=\""
          << plot_bottom + 16 << "\" text-anchor=\"middle\">" << tick_label(tick) << "</text>\n";
    }
  } else {
    for (std::size_t i = 0; i < categories_.size(); ++i) {
      out << "<text x=\"" << number(px_x(static_cast<double>(i))) << "\" y=\"" << plot_bottom + 16
          << "\" text-anchor=\"middle\">" << html_escape(categories_[i]) << "</text>\n";
    }
  }
  out << "<text x=\"" << (plot_left + plot_right) / 2 << "\" y=\"" << height_px_ - 8 << "\" text-anchor=\"middle\">"
      << html_escape(x_label_) << "</text>\n";
  out << "<text transform=\"translate(14," << (plot_top + plot_bottom) / 2 << ") rotate(-90)\" text-anchor=\"middle\">"
      << html_escape(y_label_) << "</text>\n";
  out << "<g clip-path=\"none\">\n" << body_ << "</g>\n";
  for (std::size_t i = 0; i < legend_.size(); ++i) {
    const double y = plot_top + 14 + 14 * static_cast<double>(i);
    out << "<rect x=\"" << plot_right - 150 << "\" y=\"" << y - 9 << "\" width=\"10\" height=\"10\" fill=\""
        << legend_[i].second << "\"/><text x=\"" << plot_right - 136 << "\" y=\"" << y << "\">"
        << html_escape(legend_[i].first) << "</text>\n";
  }
  out << "</svg>\n";
  return out.str();
}

}  // namespace glarelab::analysis

#pragma once
// Small SVG charts for the report, written directly (no JavaScript, no external resources):
// axes with ticks, lines, markers, bars with error bars, text. All text is XML-escaped.
#include <optional>
#include <string>
#include <vector>

namespace glarelab::analysis {

// Escapes &, <, >, " and ' for HTML/XML text and attribute values.
std::string html_escape(const std::string& text);

class SvgPlot {
 public:
  SvgPlot(std::string title, std::string x_label, std::string y_label, int width_px = 560, int height_px = 320);

  // Data ranges; a zero-width range is widened so nothing divides by zero.
  void set_x_range(double low, double high);
  void set_y_range(double low, double high);
  // Categorical x axis: category i is centred at x = i (range -0.5 .. n - 0.5).
  void set_x_categories(std::vector<std::string> names);

  void line(const std::vector<double>& x, const std::vector<double>& y, const std::string& colour, double width_px = 2.0,
            bool dashed = false);
  void markers(const std::vector<double>& x, const std::vector<double>& y, const std::string& colour, double radius_px = 3.5,
               bool hollow = false);
  void bar(double x_centre, double width, double y, const std::string& colour);
  void error_bar(double x, double low, double high, const std::string& colour = "#222");
  void horizontal_rule(double y, const std::string& colour);
  void legend(const std::string& label, const std::string& colour);
  void note(const std::string& text);  // a line under the title, e.g. "no data"

  std::string svg() const;

 private:
  double px_x(double x) const;
  double px_y(double y) const;

  std::string title_, x_label_, y_label_;
  int width_px_, height_px_;
  double x_low_ = 0.0, x_high_ = 1.0, y_low_ = 0.0, y_high_ = 1.0;
  std::vector<std::string> categories_;
  std::vector<std::pair<std::string, std::string>> legend_;
  std::vector<std::string> notes_;
  std::string body_;
};

// Colours used for the series of a figure, in order.
const std::string& series_colour(std::size_t index);

}  // namespace glarelab::analysis

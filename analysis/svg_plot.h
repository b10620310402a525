#pragma once
// Small SVG charts for the report, written directly (no JavaScript, no external resources):
// axes with ticks, lines, markers, bars with error bars, text. All text is XML-escaped.
//
// Why the project's own writer rather than PLplot's SVG driver: the figures carry classes on
// their parts (plot-area, data, legend) that the layout test reads back, the existing figure tests
// read exact attributes, identical data give byte-identical files, and no new library is needed;
// the layout rules below (wrapping, legend placement) would be the caller's work with PLplot too.
//
// Layout: figures lay themselves out from estimated text widths: titles, notes and axis labels
// wrap at spaces to the figure's width; categorical slots are at least as wide as their longest
// word (labels wrap within their slot, the figure widens with the number of categories); the
// legend stands right of the plotting area, never over the data; the plotting area moves right or
// down when tick labels, titles or notes need the room (tests/analysis_layout_test.cpp checks the
// rendered boxes in headless Chromium).
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
  // Categorical x axis: category i is centred at x = i (range -0.5 .. n - 0.5). Call before
  // drawing: it widens the figure when the labels need it.
  void set_x_categories(std::vector<std::string> names);

  void line(const std::vector<double>& x, const std::vector<double>& y, const std::string& colour, double width_px = 2.0,
            bool dashed = false);
  void markers(const std::vector<double>& x, const std::vector<double>& y, const std::string& colour, double radius_px = 3.5,
               bool hollow = false);
  void bar(double x_centre, double width, double y, const std::string& colour);
  // Intervals stay inside the plotting area: an end beyond the axis range stops at the edge and is
  // drawn as an arrowhead pointing on, not as a cap, so a clipped interval is not read as ending there.
  void error_bar(double x, double low, double high, const std::string& colour = "#222");
  // A horizontal interval at height y (e.g. a PSE's interval on the x axis).
  void horizontal_error_bar(double y, double low, double high, const std::string& colour = "#222");
  void horizontal_rule(double y, const std::string& colour);
  void legend(const std::string& label, const std::string& colour);
  void note(const std::string& text);  // a line under the title, e.g. "no data"

  std::string svg() const;

  // Pixels per unit of x on the plotting area (for offsets given in pixels).
  double px_per_x() const;

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

// A point of a series whose marker's area shows how many trials it holds.
struct CountedPoint {
  double x = 0.0;
  double y = 0.0;
  long trials = 0;
};

// Rings (hollow markers) of several series on a numeric x axis, each ring's area proportional to
// its trials, sized and set apart so that no ring hides another: the largest radius is at most
// 8 px and small enough that the series' rings at one x, set side by side (series s moved
// (s - (S - 1) / 2) (2 r_max + 1) px), fit between neighbouring x values; the smallest ring is
// 1.5 px. Returns the largest radius used.
double counted_rings(SvgPlot& plot, const std::vector<std::vector<CountedPoint>>& series,
                     const std::vector<std::string>& colours);

// Colours used for the series of a figure, in order.
const std::string& series_colour(std::size_t index);

}  // namespace glarelab::analysis
